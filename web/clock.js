// Clock & statistics view: simulated time, clock.step under manual timing, the bus counters
// of `stats`, how late replies went out, and EEPROM writes per item.
import * as api from './api.js';
import {$, el, fmt, num, setText, showMessage} from './util.js';

const kBuckets = ['1ms', '5ms', '10ms', '34ms'];
const kColours = ['#1f77b4', '#d62728', '#2ca02c', '#ff7f0e', '#9467bd', '#8c564b'];
const kHotWrites = 3;  // EEPROM items written more often than this are highlighted
const kHistory = 240;  // polls of lateness kept for the chart (a minute at 4 a second)
// The lines of the lateness chart: [key of `lateness`, label, colour (one port), dash (several)].
const kLines = [['p50_us', 'median', '#2ca02c', []], ['p99_us', 'p99', '#ff7f0e', [6, 3]], ['max_us', 'max', '#d62728', [2, 3]]];
let chart = null;
let histogram = null;
let mode = null;
let history = [];  // [{t (simulated s), ports: {port: lateness}}]

function timingOf(clock, stats) {
  // A daemon that says its timing in clock.now is believed; otherwise `stats` has `lateness`
  // only under realtime and fast timing (manual time is not the wall clock's).
  const said = clock?.timing ?? clock?.mode;
  if (typeof said === 'string') return said;
  const ports = Object.values(stats ?? {});
  if (!ports.length) return null;
  return ports.some((p) => p && typeof p.lateness === 'object') ? 'realtime or fast' : 'manual';
}

function formatTime(ms) {
  if (typeof ms !== 'number') return '?';
  const s = ms / 1000;
  const h = Math.floor(s / 3600);
  const m = Math.floor((s % 3600) / 60);
  const rest = (s % 60).toFixed(3).padStart(6, '0');
  return `${h ? `${h}:` : ''}${String(m).padStart(h ? 2 : 1, '0')}:${rest} (${num(ms, 3)} ms)`;
}

// The counters of one port, flattened: "lateness.p50_us", "lateness.over.1ms", ...
function flatten(object, prefix = '', out = {}) {
  for (const [key, value] of Object.entries(object ?? {})) {
    if (key === 'eeprom_writes') continue;
    const name = prefix ? `${prefix}.${key}` : key;
    if (value && typeof value === 'object' && !Array.isArray(value)) flatten(value, name, out);
    else out[name] = value;
  }
  return out;
}

function renderStats(stats) {
  const ports = Object.keys(stats);
  const flat = ports.map((port) => flatten(stats[port]));
  const names = [];
  for (const f of flat) for (const name of Object.keys(f)) if (!names.includes(name)) names.push(name);
  const table = $('stats-table');
  const head = ['counter', ...ports];
  if (table.dataset.head !== JSON.stringify(head) || table.tBodies[0].rows.length !== names.length) {
    table.dataset.head = JSON.stringify(head);
    table.tHead.rows[0].replaceChildren(...head.map((h) => el('th', {}, h)));
    table.tBodies[0].replaceChildren(...names.map((name) => el('tr', {dataset: {key: name}},
      el('td', {}, name), ...ports.map((port) => el('td', {class: 'num', dataset: {port}})))));
  }
  for (const row of table.tBodies[0].rows) {
    ports.forEach((port, i) => {
      const value = flat[i][row.dataset.key];
      setText(row.cells[i + 1], value === undefined ? '' : fmt(value, 1));
      row.cells[i + 1].classList.toggle('nonzero', typeof value === 'number' && value !== 0 &&
        /garbage|bad_checks|truncated|impossible|decode_errors|unread_drops|collisions|id_conflicts|faults_injected|dropped|over\./.test(row.dataset.key));
    });
  }
}

// How late replies went out (`stats` lateness, realtime and fast timing): a line each for the
// median, p99 and maximum since start, per port, against simulated time, on a log scale (a
// median of microseconds and a maximum of milliseconds on one chart); the counts past 1, 5, 10
// and 34 ms in the summary.
function renderLateness(stats, seconds) {
  const ports = Object.keys(stats).filter((port) => stats[port]?.lateness);
  const summary = ports.map((port) => {
    const l = stats[port].lateness;
    const over = kBuckets.map((b) => `> ${b.replace('ms', ' ms')}: ${l.over?.[b] ?? 0}`).join(', ');
    return `${port}: ${l.deliveries} deliveries; median ${fmt(l.p50_us, 1)} µs, p99 ${fmt(l.p99_us, 1)} µs, ` +
           `max ${fmt(l.max_us, 1)} µs; ${over}; dropped ${l.dropped ?? 0} (limit ${l.drop_after_ms} ms)`;
  });
  setText($('lateness-summary'), ports.length ? summary.join('\n')
    : 'No lateness under manual timing: simulated time is not the wall clock\'s.');
  $('lateness-chart').closest('.chart-row').hidden = !ports.length;
  if (!ports.length || typeof Chart === 'undefined') return;
  renderHistogram(stats, ports);
  if (history.length && seconds < history[history.length - 1].t) history = [];  // another daemon
  history.push({t: seconds, ports: Object.fromEntries(ports.map((port) => [port, stats[port].lateness]))});
  if (history.length > kHistory) history.splice(0, history.length - kHistory);
  if (!chart) {
    chart = new Chart($('lateness-chart'), {
      type: 'line',
      data: {datasets: []},
      options: {
        animation: false,
        responsive: true,
        maintainAspectRatio: false,
        parsing: false,
        interaction: {mode: 'nearest', axis: 'x', intersect: false},
        scales: {
          x: {type: 'linear', title: {display: true, text: 'simulated time (s)'}, ticks: {maxRotation: 0}},
          y: {type: 'logarithmic', title: {display: true, text: 'late by (µs)'},
              ticks: {callback: (value) => (Number.isInteger(Math.log10(value)) ? fmt(value) : '')}},
        },
        plugins: {legend: {position: 'top', labels: {boxWidth: 12}}},
      },
    });
  }
  const datasets = [];
  ports.slice(0, kColours.length).forEach((port, i) => {
    for (const [key, name, colour, dash] of kLines) {
      const several = ports.length > 1;
      datasets.push({
        label: several ? `${port} ${name}` : name,
        // Nothing before the first reply; a log scale has no 0: less than 1 µs shows as 1.
        data: history.filter((h) => h.ports[port]?.deliveries > 0)
          .map((h) => ({x: h.t, y: Math.max(1, h.ports[port][key] ?? 0)})),
        borderColor: several ? kColours[i] : colour,
        backgroundColor: several ? kColours[i] : colour,
        borderDash: several ? dash : [],
        borderWidth: 1.5,
        pointRadius: 0,
      });
    }
  });
  const same = chart.data.datasets.length === datasets.length &&
               datasets.every((d, i) => chart.data.datasets[i].label === d.label);
  if (same) datasets.forEach((d, i) => { chart.data.datasets[i].data = d.data; });
  else chart.data.datasets = datasets;
  chart.update('none');
}

function renderEepromWrites(stats) {
  const rows = [];
  for (const [port, counters] of Object.entries(stats)) {
    for (const [servo, itemsWritten] of Object.entries(counters?.eeprom_writes ?? {})) {
      for (const [item, writes] of Object.entries(itemsWritten)) rows.push({port, servo, item, writes});
    }
  }
  rows.sort((a, b) => b.writes - a.writes || a.port.localeCompare(b.port) || Number(a.servo) - Number(b.servo));
  const body = $('eeprom-writes').tBodies[0];
  const signature = JSON.stringify(rows);
  if (body.dataset.signature === signature) return;
  body.dataset.signature = signature;
  body.replaceChildren(...rows.map((r) => el('tr', {class: r.writes > kHotWrites ? 'hot' : '', dataset: {port: r.port, servo: r.servo, item: r.item}},
    el('td', {}, r.port), el('td', {class: 'num'}, r.servo), el('td', {}, r.item), el('td', {class: 'num'}, r.writes))));
  if (!rows.length) body.append(el('tr', {class: 'empty'}, el('td', {colspan: '4'}, 'no EEPROM item written by the bus')));
}

// The replies by how late they went out: the `over` counts made into bands (up to 1 ms, 1 ~ 5
// ms, ...), on a log scale (thousands on time, a few late).
function renderHistogram(stats, ports) {
  const labels = ['≤1', '1–5', '5–10', '10–34', '>34'];
  if (!histogram) {
    histogram = new Chart($('lateness-histogram'), {
      type: 'bar',
      data: {labels, datasets: []},
      options: {
        animation: false,
        responsive: true,
        maintainAspectRatio: false,
        scales: {
          x: {title: {display: true, text: 'late by (ms)'}, ticks: {maxRotation: 0, autoSkip: false}},
          y: {type: 'logarithmic', min: 0.5, title: {display: true, text: 'replies'},
              ticks: {callback: (value) => (Number.isInteger(Math.log10(value)) ? fmt(value) : '')}},
        },
        plugins: {legend: {display: ports.length > 1, position: 'top', labels: {boxWidth: 12}}},
      },
    });
  }
  const datasets = ports.slice(0, kColours.length).map((port, i) => {
    const l = stats[port].lateness;
    const over = kBuckets.map((b) => l.over?.[b] ?? 0);
    const counts = [l.deliveries - over[0], over[0] - over[1], over[1] - over[2], over[2] - over[3], over[3]];
    return {label: port, data: counts.map((n) => (n > 0 ? n : null)), backgroundColor: kColours[i]};
  });
  const same = histogram.data.datasets.length === datasets.length &&
               datasets.every((d, i) => histogram.data.datasets[i].label === d.label);
  if (same) datasets.forEach((d, i) => { histogram.data.datasets[i].data = d.data; });
  else histogram.data.datasets = datasets;
  histogram.options.plugins.legend.display = ports.length > 1;
  histogram.update('none');
}

async function poll() {
  const [clock, stats] = await Promise.all([api.call('clock.now'), api.call('stats')]);
  setText($('clock-now'), formatTime(clock.ms));
  mode = timingOf(clock, stats);
  setText($('clock-mode'), mode ?? '?');
  const manual = mode === 'manual';
  $('clock-step').disabled = !manual;
  $('clock-step-ms').disabled = !manual;
  $('clock-step').title = manual ? 'clock.step: move simulated time forward' : 'clock.step needs --timing manual';
  renderStats(stats);
  renderLateness(stats, clock.ms / 1000);
  renderEepromWrites(stats);
}

function init() {
  $('clock-step').addEventListener('click', async () => {
    const ms = Number($('clock-step-ms').value);
    if (!(ms > 0)) {
      showMessage($('clock-message'), 'the step is a positive number of ms', false);
      return;
    }
    // clock.step takes one of ms, us, ns: whole microseconds go as us, to keep fractions exact.
    const args = Number.isInteger(ms) ? {ms} : {us: Math.round(ms * 1000)};
    const reply = await api.request({cmd: 'clock.step', ...args}).catch(() => null);
    if (reply) showMessage($('clock-message'), reply.ok ? `now ${reply.result.ms} ms` : reply.error, reply.ok);
    await poll().catch(() => {});
  });
}

export default {
  name: 'clock',
  periodMs: 250,
  init,
  poll,
};
