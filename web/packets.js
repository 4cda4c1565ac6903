// Packets view: every packet both ways from `trace.subscribe` (docs/trace.md), filtered, with
// downloads as JSON lines and as a pcap capture.
import * as api from './api.js';
import * as servos from './servos.js';
import {buildPcap} from './pcap.js';
import {$, download, escapeHtml, fillSelect, stamp} from './util.js';

const kKeep = 10000;   // records kept for the downloads
const kShow = 500;     // rows drawn
const kRenderMs = 250; // at most 4 redraws a second
const kLateUs = 1000;  // a reply later than this (µs) against its modelled time is highlighted

let records = [];      // {record (without "event"), parsed}
let visible = false;
let paused = false;
let subscribed = false;
let dirty = true;
let renderTimer = null;
let changing = Promise.resolve();

/** Splits a record's `packet` text into ID, instruction, fields and error. */
function parse(record) {
  const result = {id: record.id ?? '', instruction: '', fields: '', error: ''};
  const text = typeof record.packet === 'string' ? record.packet : '';
  if (!text) {
    result.error = record.problem ?? '';
    if (record.bytes !== undefined) result.fields = `${record.bytes} bytes`;
    return result;
  }
  const match = /^id=(\d+)\s*(.*)$/s.exec(text);
  if (!match) {
    result.fields = text;
    return result;
  }
  result.id = Number(match[1]);
  const rest = match[2];
  if (record.dir === 'out') {
    // A status ("error=0x00 params=..."), a Fast reply, or several deliveries joined by "; ".
    const errors = [...text.matchAll(/error=0x([0-9A-Fa-f]+)/g)].filter((m) => Number.parseInt(m[1], 16) !== 0);
    if (errors.length) result.error = errors.map((m) => m[0]).join(' ');
    if (/^error=/.test(rest)) {
      result.instruction = 'status';
      result.fields = rest.replace(/^error=0x[0-9A-Fa-f]+\s*/, '');
    } else {
      const word = /^(\S+)\s*(.*)$/s.exec(rest);
      result.instruction = word ? word[1] : '';
      result.fields = word ? word[2] : '';
    }
    if (/undecodable status/.test(text)) result.error = result.error || 'undecodable status';
  } else {
    const word = /^(\S+)\s*(.*)$/s.exec(rest);
    result.instruction = word ? word[1] : '';
    result.fields = word ? word[2] : '';
  }
  if (record.problem) result.error = result.error ? `${result.error} ${record.problem}` : record.problem;
  return result;
}

function onTrace(event) {
  if (paused) return;
  const {event: _, ...record} = event;
  records.push({record, parsed: parse(record)});
  if (records.length > kKeep) records.splice(0, records.length - kKeep);
  dirty = true;
}

function filters() {
  const id = $('pkt-filter-id').value.trim();
  return {
    port: $('pkt-filter-port').value,
    id: id === '' ? null : Number(id),
    dir: $('pkt-filter-dir').value,
    text: $('pkt-filter-text').value.trim().toLowerCase(),
  };
}

function matches(entry, f) {
  const {record, parsed} = entry;
  if (f.port && record.port !== f.port) return false;
  if (f.dir && record.dir !== f.dir) return false;
  if (f.id !== null && parsed.id !== f.id) return false;
  if (f.text) {
    const haystack = `${parsed.instruction} ${parsed.fields} ${parsed.error} ${record.hex ?? ''}`.toLowerCase();
    if (!haystack.includes(f.text)) return false;
  }
  return true;
}

function render() {
  if (!visible || !dirty) return;
  dirty = false;
  const f = filters();
  const shown = [];
  let matched = 0;
  for (let i = records.length - 1; i >= 0; i--) {
    if (!matches(records[i], f)) continue;
    matched++;
    if (shown.length < kShow) shown.push(records[i]);
  }
  shown.reverse();
  const box = $('packets-table').closest('.scroll-box');
  const atBottom = box.scrollTop + box.clientHeight >= box.scrollHeight - 30;
  const html = shown.map(({record, parsed}) => {
    const classes = [record.dir === 'out' ? 'out' : 'in', parsed.error ? 'err' : ''].join(' ');
    const t = typeof record.t === 'number' ? record.t.toFixed(6) : '';
    return `<tr class="${classes}" title="${escapeHtml(record.hex ?? '')}"><td class="num">${t}</td><td>${escapeHtml(record.port ?? '')}</td>` +
      `<td>${escapeHtml(record.dir ?? '')}</td><td class="num">${escapeHtml(parsed.id)}</td><td>${escapeHtml(parsed.instruction)}</td>` +
      `<td class="fields">${escapeHtml(parsed.fields)}</td><td>${escapeHtml(parsed.error)}</td>` +
      `<td class="num${record.late_us > kLateUs ? ' late' : ''}">${typeof record.late_us === 'number' ? escapeHtml(Math.round(record.late_us)) : ''}</td></tr>`;
  }).join('');
  $('packets-table').tBodies[0].innerHTML = html;
  if (atBottom) box.scrollTop = box.scrollHeight;
  $('pkt-count').textContent = `${records.length} kept, ${matched} match, last ${shown.length} shown${subscribed ? '' : ' (not capturing)'}`;
}

/** Subscribes while the view is shown or recording (and not paused), unsubscribes otherwise. */
function update() {
  changing = changing.then(async () => {
    if (!api.isConnected()) {
      subscribed = false;
      return;
    }
    const want = !paused && (visible || $('pkt-record').checked);
    if (want === subscribed) return;
    try {
      await api.call(want ? 'trace.subscribe' : 'trace.unsubscribe');
      subscribed = want;
    } catch (error) {
      if (error.message !== 'disconnected') $('pkt-count').textContent = `trace.subscribe refused: ${error.message}`;
    }
    dirty = true;
  });
  return changing;
}

function jsonl() {
  return records.map(({record}) => `${JSON.stringify(record)}\n`).join('');
}

function pcap() {
  return buildPcap(records.map(({record}) => record), servos.portIndex);
}

function init() {
  api.on('trace', onTrace);
  $('pkt-record').addEventListener('change', update);
  $('pkt-pause').addEventListener('click', () => {
    paused = !paused;
    $('pkt-pause').textContent = paused ? 'Resume' : 'Pause';
    $('pkt-pause').classList.toggle('on', paused);
    update();
  });
  $('pkt-clear').addEventListener('click', () => {
    records = [];
    dirty = true;
    render();
  });
  $('pkt-jsonl').addEventListener('click', () => download(`dxlemu-trace-${stamp()}.jsonl`, jsonl(), 'application/x-ndjson'));
  $('pkt-pcap').addEventListener('click', () => download(`dxlemu-${stamp()}.pcap`, new Blob([pcap()], {type: 'application/vnd.tcpdump.pcap'})));
  for (const id of ['pkt-filter-port', 'pkt-filter-id', 'pkt-filter-dir', 'pkt-filter-text']) {
    $(id).addEventListener('input', () => {
      dirty = true;
      render();
    });
  }
}

async function poll() {
  await servos.refresh();
  fillSelect($('pkt-filter-port'), [['', 'all'], ...(servos.list().ports ?? []).map((p) => [p.name, p.name])]);
}

export default {
  name: 'packets',
  periodMs: 2000,
  init,
  poll,
  show() {
    visible = true;
    dirty = true;
    renderTimer ??= setInterval(render, kRenderMs);
    render();
    update();
  },
  hide() {
    visible = false;
    clearInterval(renderTimer);
    renderTimer = null;
    update();
  },
  connected() {
    subscribed = false;
    return update();
  },
  jsonl,
  pcap,
};
