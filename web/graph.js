// Graph view: up to 10 items of any servos against simulated time, from `sample.subscribe`,
// drawn with Chart.js (global Chart, Debian's libjs-chart.js).
import * as api from './api.js';
import * as servos from './servos.js';
import {$, download, downloadUrl, el, fillSelect, parseServoKey, servoKey, showMessage, stamp} from './util.js';

const kMaxItems = 10;
const kMaxRows = 200000;  // samples kept for the CSV (at 10 ms: over half an hour)
const kDrawMs = 100;
const kColours = ['#1f77b4', '#d62728', '#2ca02c', '#ff7f0e', '#9467bd', '#8c564b', '#e377c2', '#17becf', '#7f7f7f', '#bcbd22'];
// Offered when the daemon has no `table` to list a servo's items.
const kCommonItems = ['present_position', 'goal_position', 'present_velocity', 'present_current', 'present_load',
  'present_temperature', 'present_input_voltage', 'present_voltage', 'hardware_error_status', 'moving'];

let items = [];        // [{port, servo, item}] as the page wants them
let subscribed = null; // the items and period of the subscription the daemon confirmed
let accepting = false; // false between sending a subscription and its reply: older events are stale
let paused = false;
let rows = [];         // [{t, values}] since the subscription began
let rowsSignature = ''; // the item labels `rows` holds values of
let chart = null;
let visible = false;
let dirty = false;
let drawTimer = null;
let subscribing = Promise.resolve();

function label(item) {
  return `${item.port}/${item.servo}/${item.item}`;
}

function period() {
  const value = Number($('graph-period').value);
  return Number.isFinite(value) && value >= 1 && value <= 1000 ? value : null;
}

function windowSeconds() {
  const value = Number($('graph-window').value);
  return Number.isFinite(value) && value > 0 ? value : 10;
}

function renderItems() {
  $('graph-items').replaceChildren(...items.map((item, index) => el('li', {dataset: {index: String(index)}},
    el('span', {class: 'swatch', style: `background:${kColours[index % kColours.length]}`}),
    label(item),
    el('button', {type: 'button', class: 'remove', title: 'remove', dataset: {index: String(index)}}, '×'))));
  $('graph-add').disabled = items.length >= kMaxItems;
}

/** Subscribes to what `items` and the period say now (or unsubscribes), one request at a time. */
function resubscribe() {
  subscribing = subscribing.then(async () => {
    if (!api.isConnected()) return;
    accepting = false;
    const periodMs = period();
    const want = !paused && items.length > 0 && periodMs !== null;
    try {
      if (!want) {
        if (subscribed) await api.call('sample.unsubscribe');
        subscribed = null;
        return;
      }
      const result = await api.call('sample.subscribe', {items: items.map((i) => ({...i})), period_ms: periodMs});
      subscribed = {items: result.items ?? items, period: result.period_ms ?? periodMs};
      // Samples of the same items go on in the same table (after a pause, a new period or a
      // reconnection); other items start a new one.
      const signature = subscribed.items.map(label).join(',');
      if (signature !== rowsSignature) {
        rowsSignature = signature;
        rows = [];
        resetChart();
      }
      accepting = true;
      showMessage($('graph-message'), '', true);
    } catch (error) {
      subscribed = null;
      if (error.message !== 'disconnected') showMessage($('graph-message'), `sample.subscribe refused: ${error.message}`, false);
    }
  });
  return subscribing;
}

function onSample(event) {
  if (!accepting || paused || !subscribed || !Array.isArray(event.values)) return;
  if (event.values.length !== subscribed.items.length) return;
  rows.push({t: event.t, values: event.values});
  if (rows.length > kMaxRows) rows.splice(0, rows.length - kMaxRows);
  dirty = true;
}

// The time axis's labels, but none on a scrolling window's left edge (an odd time, closer to the
// next label than the labels are to each other).
function timeTick(value, index, ticks) {
  if (index === 0 && ticks.length > 2 && ticks[1].value - value < 0.999 * (ticks[2].value - ticks[1].value)) return '';
  return Chart.Ticks.formatters.numeric.call(this, value, index, ticks);
}

// The y axes: one per item key (the present_position of three servos share one), stacked one
// above the other when there are several, so that a temperature is not a flat line under a
// position's thousands.
function axesFor(shown) {
  const keys = [...new Set(shown.map((item) => item.item))];
  const scales = {
    x: {type: 'linear', title: {display: true, text: 'simulated time (s)'}, ticks: {maxRotation: 0, callback: timeTick}},
  };
  keys.forEach((key, index) => {
    scales[`y${index}`] = {
      type: 'linear',
      position: 'left',
      stack: keys.length > 1 ? 'items' : undefined,
      stackWeight: 1,
      weight: -index,
      offset: keys.length > 1,
      grace: '5%',
      title: {display: true, text: keys.length > 1 ? key : `${key} (as get reads it)`},
      ticks: {maxTicksLimit: keys.length > 2 ? 4 : 8},
    };
  });
  // (A stack on the left is laid out from the top by decreasing `weight`: the first item's on top.)
  return {scales, axisOf: (item) => `y${keys.indexOf(item.item)}`};
}

function resetChart() {
  if (!chart) return;
  const shown = subscribed?.items ?? [];
  const {scales, axisOf} = axesFor(shown);
  chart.options.scales = scales;
  chart.data.datasets = shown.map((item, index) => ({
    label: label(item),
    data: [],
    yAxisID: axisOf(item),
    borderColor: kColours[index % kColours.length],
    backgroundColor: kColours[index % kColours.length],
    borderWidth: 1.5,
    pointRadius: 0,
    spanGaps: false,
  }));
  chart.update('none');
}

function draw() {
  if (!chart || !dirty || !visible || paused) return;
  dirty = false;
  const span = windowSeconds();
  const last = rows.length ? rows[rows.length - 1].t : 0;
  const from = last - span;
  let first = rows.length;
  while (first > 0 && rows[first - 1].t >= from) first--;
  const shown = rows.slice(first);
  chart.data.datasets.forEach((dataset, index) => {
    dataset.data = shown.map((row) => ({x: row.t, y: typeof row.values[index] === 'number' ? row.values[index] : null}));
  });
  // The trace starts at the left edge and grows to the right until the window is full, then scrolls.
  // (From a round time: the axis's first label is its minimum.)
  const step = 10 ** Math.floor(Math.log10(span / 2));
  const start = rows.length ? Math.max(Math.floor(rows[0].t / step) * step, from) : 0;
  chart.options.scales.x.min = start;
  chart.options.scales.x.max = Math.max(last, start + span);
  chart.update('none');
  $('graph-count').textContent = `${rows.length} samples`;
}

// Paints the canvas white under the chart, so that the PNG is not transparent.
const whiteBackground = {
  id: 'whiteBackground',
  beforeDraw(c) {
    const {ctx} = c;
    ctx.save();
    ctx.globalCompositeOperation = 'destination-over';
    ctx.fillStyle = '#ffffff';
    ctx.fillRect(0, 0, c.width, c.height);
    ctx.restore();
  },
};

function makeChart() {
  if (chart || typeof Chart === 'undefined') return;
  chart = new Chart($('graph-canvas'), {
    type: 'line',
    data: {datasets: []},
    plugins: [whiteBackground],
    options: {
      animation: false,
      parsing: false,
      normalized: true,
      responsive: true,
      maintainAspectRatio: false,
      interaction: {mode: 'nearest', axis: 'x', intersect: false},
      scales: axesFor([]).scales,
      plugins: {legend: {position: 'top', labels: {boxWidth: 12}}, tooltip: {enabled: true}},
    },
  });
  resetChart();
}

function updateItemSelect() {
  const key = $('graph-servo').value;
  if (!key) {
    fillSelect($('graph-item'), []);
    return;
  }
  const {port, servo} = parseServoKey(key);
  const model = servos.servos().find((s) => s.key === key)?.model ?? '';
  const info = servos.infoNow(port, servo, model);
  const keys = info?.keys ?? kCommonItems;
  fillSelect($('graph-item'), keys.map((k) => [k, k]));
  if (!$('graph-item').dataset.chosen && keys.includes('present_position')) {
    $('graph-item').value = 'present_position';
  }
}

/** The samples as CSV: `t_s,<port>/<id>/<item>,...`, one row per sample event. */
function csv() {
  const names = rowsSignature ? rowsSignature.split(',') : items.map(label);
  const lines = [['t_s', ...names].join(',')];
  for (const row of rows) {
    lines.push([row.t, ...row.values.map((v) => (v === null || v === undefined ? '' : v))].join(','));
  }
  return `${lines.join('\n')}\n`;
}

/** Adds an item to the graph (the Add button, and window.dxlemu.graphAdd for tests); resolves
 *  once the daemon has the new subscription. */
function add(port, servo, item) {
  if (items.length >= kMaxItems) {
    showMessage($('graph-message'), `at most ${kMaxItems} items`, false);
    return subscribing;
  }
  if (items.some((i) => i.port === port && i.servo === servo && i.item === item)) return subscribing;
  items.push({port, servo, item});
  renderItems();
  return resubscribe();
}

/** Removes every item (window.dxlemu.graphClear). */
function clear() {
  items = [];
  renderItems();
  return resubscribe();
}

function init() {
  $('graph-servo').addEventListener('change', () => {
    delete $('graph-item').dataset.chosen;
    updateItemSelect();
  });
  $('graph-item').addEventListener('change', () => { $('graph-item').dataset.chosen = '1'; });
  $('graph-add').addEventListener('click', () => {
    const key = $('graph-servo').value;
    const item = $('graph-item').value;
    if (!key || !item) return;
    const {port, servo} = parseServoKey(key);
    add(port, servo, item);
  });
  $('graph-items').addEventListener('click', (event) => {
    const button = event.target.closest('button.remove');
    if (!button) return;
    items.splice(Number(button.dataset.index), 1);
    renderItems();
    resubscribe();
  });
  $('graph-period').addEventListener('change', () => {
    if (period() === null) {
      showMessage($('graph-message'), 'the period is 1 ~ 1000 ms', false);
      return;
    }
    resubscribe();
  });
  $('graph-window').addEventListener('change', () => { dirty = true; draw(); });
  $('graph-pause').addEventListener('click', () => {
    paused = !paused;
    $('graph-pause').textContent = paused ? 'Resume' : 'Pause';
    $('graph-pause').classList.toggle('on', paused);
    resubscribe();
  });
  $('graph-csv').addEventListener('click', () => download(`dxlemu-graph-${stamp()}.csv`, csv(), 'text/csv'));
  $('graph-png').addEventListener('click', () => {
    if (chart) downloadUrl(`dxlemu-graph-${stamp()}.png`, $('graph-canvas').toDataURL('image/png'));
  });
  api.on('sample', onSample);
  renderItems();
}

async function poll() {
  await servos.refresh();
  fillSelect($('graph-servo'), servos.servoOptions());
  updateItemSelect();
}

export default {
  name: 'graph',
  periodMs: 1000,
  init,
  poll,
  show() {
    visible = true;
    makeChart();
    dirty = true;
    draw();
    drawTimer ??= setInterval(draw, kDrawMs);
  },
  hide() {
    visible = false;
    clearInterval(drawTimer);
    drawTimer = null;
  },
  connected() {
    subscribed = null;
    return resubscribe();
  },
  csv,
  add,
  clear,
};
