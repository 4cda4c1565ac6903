// Control table view: every item of one servo from `table`, raw values editable with `set`.
import * as api from './api.js';
import * as servos from './servos.js';
import {$, el, fillSelect, num, parseInteger, parseServoKey, parseUnit, setText, showMessage} from './util.js';

let rowsOf = '';     // "port/id/model" the rows were built for
let items = new Map();  // key -> the last table item
let editing = null;  // the key whose raw value is being edited

// Units the model files write without a figure: the raw value is already in them.
const kPlainUnits = /^(°C|°|V|mV|A|mA|%|s|ms|us|µs|μs|Hz|rpm|RPM|N·m)$/;

function selected() {
  const value = $('servo-select').value;
  return value ? parseServoKey(value) : null;
}

function rangeText(item) {
  if (Array.isArray(item.values)) return item.values.join(', ');
  if (item.min !== undefined && item.max !== undefined) return `${item.min} ~ ${item.max}`;
  return '';
}

function scaledText(item) {
  if (typeof item.scaled === 'number') return `${num(item.scaled)} ${item.scaled_unit ?? ''}`.trim();
  if (typeof item.value !== 'number' || typeof item.unit !== 'string') return '';
  const unit = item.unit.trim();
  if (kPlainUnits.test(unit)) return `${item.value} ${unit}`;
  // A daemon without `scaled`: the same scaling here.
  const parsed = item.scaled === undefined ? parseUnit(unit) : null;
  return parsed ? `${num(item.value * parsed.factor)} ${parsed.unit}` : '';
}

function buildRows(result) {
  const body = $('ct-table').tBodies[0];
  body.replaceChildren(...result.items.map((item) => el('tr', {dataset: {key: item.key}, class: String(item.area ?? '').toLowerCase()},
    el('td', {class: 'num'}, item.address),
    el('td', {title: item.key}, item.name ?? item.key),
    el('td', {class: 'num'}, item.size),
    el('td', {class: 'access'}, item.access ?? ''),
    el('td', {class: 'area'}, item.area ?? ''),
    el('td', {class: 'num'}, rangeText(item)),
    el('td', {class: 'unit'}, item.unit ?? ''),
    el('td', {class: 'raw num', title: item.access === 'R' ? 'read-only on the bus; set forces it device-side' : 'click to change'}),
    el('td', {class: 'scaled num'}))));
}

function render(result) {
  const signature = `${result.port}/${result.servo}/${result.model}`;
  if (signature !== rowsOf) {
    rowsOf = signature;
    editing = null;
    buildRows(result);
  }
  items = new Map(result.items.map((item) => [item.key, item]));
  for (const row of $('ct-table').tBodies[0].rows) {
    const item = items.get(row.dataset.key);
    if (!item) continue;
    if (editing !== item.key) setText(row.querySelector('td.raw'), item.value ?? '');
    setText(row.querySelector('td.scaled'), scaledText(item));
  }
  const torque = items.get('torque_enable') ?? items.get('torque_switch');
  $('btn-torque').disabled = !torque;
  $('btn-torque').textContent = torque ? `Torque ${torque.value ? 'on' : 'off'}` : 'Torque';
  $('btn-torque').classList.toggle('on', !!torque?.value);
  const led = items.get('led') ?? items.get('led_red');
  $('btn-led').disabled = !led;
  $('btn-led').textContent = led ? `LED ${led.value ? 'on' : 'off'}` : 'LED';
  $('btn-led').classList.toggle('on', !!led?.value);
}

async function refresh() {
  fillSelect($('servo-select'), servos.servoOptions());
  const target = selected();
  if (!target) {
    $('ct-table').tBodies[0].replaceChildren();
    rowsOf = '';
    return;
  }
  const servo = servos.servos().find((s) => s.port === target.port && s.id === target.servo);
  // Factory Reset keeps the ID (and baud) only in Protocol 2.0, as on the wire.
  const keep = $('factory-reset-keep');
  for (const option of keep.options) option.disabled = option.value !== 'none' && servo?.protocol !== 2;
  if (keep.selectedOptions[0]?.disabled) keep.value = 'none';
  $('btn-unplug').disabled = servo?.attached === false;
  $('btn-replug').disabled = servo?.attached !== false;
  let result;
  try {
    result = await servos.table(target.port, target.servo);
  } catch (error) {
    if (!(error instanceof api.ApiError)) throw error;
    // E.g. two servos sharing an ID after a factory reset: say why in place of the values.
    const text = `table refused: ${error.message}`;
    const body = $('ct-table').tBodies[0];
    if (rowsOf !== '' || body.textContent !== text) {
      body.replaceChildren(el('tr', {class: 'empty refused'}, el('td', {colspan: '9'}, text)));
    }
    rowsOf = '';
    return;
  }
  if (result === null) {
    showMessage($('ct-message'), 'this daemon has no "table" command: the control table view needs a newer dxlemu', false);
    return;
  }
  // The servo may have changed meanwhile (a new selection): draw only the one asked for.
  const now = selected();
  if (now && now.port === target.port && now.servo === target.servo) render(result);
}

async function poll() {
  await servos.refresh();
  await refresh();
}

/** Sends one request about the selected servo; shows the refusal or `done` in #ct-message. */
async function act(cmd, args, done) {
  const target = selected();
  if (!target) return;
  try {
    const result = await api.call(cmd, {port: target.port, servo: target.servo, ...args});
    showMessage($('ct-message'), typeof done === 'function' ? done(result) : done, true);
    if (cmd === 'servo.factory_reset' || (cmd === 'set' && ['id', 'baud_rate', 'protocol_type'].includes(args.item))) {
      servos.forget();
    }
    // A new ID (a set of `id`, a factory reset): follow the servo to it.
    const newId = cmd === 'set' && args.item === 'id' ? result?.value : cmd === 'servo.factory_reset' ? result?.servo : undefined;
    if (typeof newId === 'number') {
      await servos.refresh();
      fillSelect($('servo-select'), servos.servoOptions());
      $('servo-select').value = `${target.port}/${newId}`;
    }
  } catch (error) {
    showMessage($('ct-message'), `${cmd} refused: ${error.message}`, false);
  }
  try {
    await poll();
  } catch (error) {
    // The poll loop reports it.
  }
}

function startEdit(cell) {
  const row = cell.closest('tr');
  const key = row.dataset.key;
  if (editing === key) return;
  editing = key;
  const input = el('input', {type: 'text', value: cell.textContent, class: 'edit', size: 10, spellcheck: false});
  cell.replaceChildren(input);
  input.focus();
  input.select();
  const finish = () => {
    editing = null;
    setText(cell, items.get(key)?.value ?? '');
  };
  input.addEventListener('keydown', async (event) => {
    if (event.key === 'Escape') {
      event.preventDefault();
      finish();
    } else if (event.key === 'Enter') {
      event.preventDefault();
      const value = parseInteger(input.value);
      if (value === null) {
        showMessage($('ct-message'), `"${input.value}" is not an integer`, false);
        return;
      }
      finish();
      await act('set', {item: key, value}, (result) => `${key} set to ${result?.value ?? value}`);
    }
  });
  input.addEventListener('blur', () => {
    if (editing === key) finish();
  });
}

function init() {
  $('servo-select').addEventListener('change', () => {
    showMessage($('ct-message'), '', true);
    poll().catch(() => {});
  });
  $('ct-table').addEventListener('click', (event) => {
    const cell = event.target.closest('td.raw');
    if (cell && !cell.querySelector('input')) startEdit(cell);
  });
  $('btn-torque').addEventListener('click', () => {
    const item = items.get('torque_enable') ?? items.get('torque_switch');
    if (item) act('set', {item: item.key, value: item.value ? 0 : 1}, `${item.key} ${item.value ? 0 : 1}`);
  });
  $('btn-led').addEventListener('click', () => {
    const item = items.get('led') ?? items.get('led_red');
    if (item) act('set', {item: item.key, value: item.value ? 0 : 1}, `${item.key} ${item.value ? 0 : 1}`);
  });
  $('btn-reboot').addEventListener('click', () => act('servo.reboot', {}, 'rebooted'));
  $('btn-factory-reset').addEventListener('click', () =>
    act('servo.factory_reset', {keep: $('factory-reset-keep').value},
        (result) => `factory reset: now ID ${result?.servo ?? '?'}, booting`));
  $('btn-power-cycle').addEventListener('click', () => act('servo.power_cycle', {}, 'power cycled: booting'));
  $('btn-unplug').addEventListener('click', () => act('servo.detach', {}, 'unplugged'));
  $('btn-replug').addEventListener('click', () => act('servo.attach', {}, 'plugged in: booting'));
}

export default {
  name: 'table',
  periodMs: 250,
  init,
  poll,
  connected: () => { rowsOf = ''; },
};
