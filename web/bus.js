// Bus view: one row per servo of every port, from `list`, with firmware and supply voltage.
import * as api from './api.js';
import * as servos from './servos.js';
import {$, el, setText, showMessage} from './util.js';

// The columns in order: [key, header, title]. Keys of `list` not named here are appended.
const kColumns = [
  ['port', 'port'],
  ['id', 'ID'],
  ['model', 'model'],
  ['firmware_version', 'firmware', 'Firmware Version (FEETECH: major.minor)'],
  ['protocol', 'protocol'],
  ['baud', 'baud'],
  ['torque', 'torque', 'Torque Enable (Torque switch on FEETECH)'],
  ['moving', 'moving'],
  ['present_position', 'position', 'Present Position'],
  ['present_temperature', 'temp (°C)', 'Present Temperature; red above its Temperature Limit'],
  ['present_input_voltage', 'voltage (V)', 'Present Input Voltage (FEETECH: Present voltage), in volts'],
  ['hardware_error_status', 'hw error', 'Hardware Error Status'],
  ['servo_status', 'servo status', 'FEETECH Servo status (address 65)'],
  ['attached', 'attached', 'plugged in (servo.detach / servo.attach)'],
];
const kAlwaysShown = new Set(['port', 'id', 'model', 'firmware_version', 'present_input_voltage']);
const kNumeric = new Set(['id', 'baud', 'present_position', 'present_temperature', 'present_input_voltage']);
let columns = [];
const voltages = new Map();  // "port/id" -> volts

function format(key, value, servo) {
  if (value === undefined || value === null) return '';
  switch (key) {
    case 'torque': return value ? 'on' : 'off';
    case 'moving': case 'attached': case 'booting': return value ? 'yes' : 'no';
    case 'hardware_error_status': case 'servo_status':
      return typeof value === 'number' ? `0x${value.toString(16).toUpperCase().padStart(2, '0')}` : String(value);
    case 'present_input_voltage': return typeof value === 'number' ? value.toFixed(1) : String(value);
    case 'protocol': return ({feetech: 'FEETECH', modbus: 'Modbus RTU'})[servo.protocol] ?? String(value);
    default: return typeof value === 'object' ? JSON.stringify(value) : String(value);
  }
}

function layout(all) {
  const present = new Set(['port', 'model', 'id']);
  for (const servo of all) for (const key of Object.keys(servo)) present.add(key);
  const chosen = kColumns.filter(([key]) => kAlwaysShown.has(key) || present.has(key));
  const known = new Set(kColumns.map(([key]) => key).concat(['key', 'label']));
  for (const key of present) if (!known.has(key)) chosen.push([key, key.replace(/_/g, ' ')]);
  if (JSON.stringify(chosen) === JSON.stringify(columns)) return;
  columns = chosen;
  const head = $('bus-table').tHead.rows[0];
  head.replaceChildren(...columns.map(([key, label, title]) => el('th', {dataset: {key}, title, class: kNumeric.has(key) ? 'num' : ''}, label)));
  $('bus-table').tBodies[0].replaceChildren();
}

// One line per port: its PTY, the link a client opens, how many servos.
function renderPorts() {
  const ports = servos.list().ports ?? [];
  const text = ports.map((port) => {
    const count = (port.servos ?? []).length;
    const where = [port.link && `link ${port.link}`, port.pty && `PTY ${port.pty}`].filter(Boolean).join(', ');
    return `${port.name}: ${count} servo${count === 1 ? '' : 's'}${where ? ` on ${where}` : ''}`;
  });
  setText($('bus-ports'), text.join('   ·   '));
}

function render() {
  const all = servos.servos();
  layout(all);
  renderPorts();
  const body = $('bus-table').tBodies[0];
  // Rows by port, ID and which of the servos of that ID (after a factory reset or a new ID two
  // servos may share one: both are listed, in red).
  const rowKey = (port, id, nth) => `${port}/${id}#${nth}`;
  const rows = new Map();
  const seen = new Map();
  for (const row of body.rows) {
    const key = `${row.dataset.port}/${row.dataset.servo}`;
    const nth = seen.get(key) ?? 0;
    seen.set(key, nth + 1);
    rows.set(rowKey(row.dataset.port, row.dataset.servo, nth), row);
  }
  const shared = new Map();
  for (const servo of all) shared.set(servo.key, (shared.get(servo.key) ?? 0) + 1);
  seen.clear();
  const wanted = [];
  for (const servo of all) {
    const nth = seen.get(servo.key) ?? 0;
    seen.set(servo.key, nth + 1);
    const key = rowKey(servo.port, servo.id, nth);
    let row = rows.get(key);
    if (!row || row.cells.length !== columns.length) {
      row = el('tr', {dataset: {port: servo.port, servo: String(servo.id)}},
               ...columns.map(([column]) => el('td', {dataset: {key: column}, class: kNumeric.has(column) ? 'num' : ''})));
    }
    rows.delete(key);
    const info = servos.infoNow(servo.port, servo.id, servo.model);
    // `list` gives both raw (a daemon older than that: `get`); the cells show volts, and the
    // FEETECH firmware as major.minor when the table says the minor.
    const rawVoltage = servo.present_input_voltage;
    const values = {
      ...servo,
      firmware_version: info?.firmware || servo.firmware_version,
      present_input_voltage: typeof rawVoltage === 'number' ? rawVoltage * (info?.voltageScale ?? 0.1) : voltages.get(servo.key),
    };
    columns.forEach(([key], i) => setText(row.cells[i], format(key, values[key], servo)));
    const limit = info?.temperatureLimit;
    const hot = typeof limit === 'number' && typeof servo.present_temperature === 'number' &&
                servo.present_temperature > limit;
    const errorBits = (servo.hardware_error_status ?? 0) !== 0 || (servo.servo_status ?? 0) !== 0;
    const conflict = shared.get(servo.key) > 1;
    row.classList.toggle('alarm', errorBits || servo.attached === false || hot || conflict);
    row.title = conflict ? `${shared.get(servo.key)} servos on ${servo.port} share ID ${servo.id}: the controller cannot tell them apart` : '';
    const temperature = row.querySelector('td[data-key="present_temperature"]');
    if (temperature) {
      temperature.classList.toggle('hot', hot);
      temperature.title = typeof limit === 'number' ? `limit ${limit} °C` : '';
    }
    wanted.push(row);
  }
  // Keep the rows in list order, moving only what moved.
  wanted.forEach((row, i) => {
    if (body.rows[i] !== row) body.insertBefore(row, body.rows[i] ?? null);
  });
  while (body.rows.length > wanted.length) body.rows[wanted.length].remove();
  showMessage($('bus-message'), all.length ? '' : 'no servos', false);
}

async function poll() {
  await servos.refresh();
  // A daemon whose `list` has no supply voltage: one `get` per servo, all in one message.
  const asks = servos.servos().map(async (servo) => {
    if (servo.present_input_voltage !== undefined) return;
    const info = servos.infoNow(servo.port, servo.id, servo.model);
    if (!info?.voltageKey) return;
    const reply = await api.request({cmd: 'get', port: servo.port, servo: servo.id, item: info.voltageKey}, {quiet: true});
    if (reply.ok) voltages.set(servo.key, reply.result.value * info.voltageScale);
    else voltages.delete(servo.key);
  });
  await Promise.all(asks);
  render();
}

export default {
  name: 'bus',
  periodMs: 250,
  poll,
};
