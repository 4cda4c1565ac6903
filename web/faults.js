// Faults & conditions view: fault rules (docs/faults.md), presets, the world around a servo
// (condition.set) and scenarios.
import * as api from './api.js';
import * as servos from './servos.js';
import {$, el, fillSelect, fmt, num, parseServoKey, setText, showMessage} from './util.js';

// Each preset: a title saying what it does, and the request(s) it makes for {port, servo}.
const kPresets = {
  overheat: {
    title: 'fault.add hardware_error "overheating" on the servo: Hardware Error Status gets the Overheating bit, ' +
           'torque turns off and every status carries the alert bit, as a motor past its Temperature Limit. ' +
           'Remove the rule, then reboot the servo to clear it.',
    requests: ({port, servo}) => [{cmd: 'fault.add', rule: {action: 'hardware_error', kind: 'overheating', match: {port, servos: [servo]}}}],
  },
  overload: {
    title: 'fault.add hardware_error "overload" on the servo: the Overload Error of a shaft held against more than it can give ' +
           '(torque off on X series). Remove the rule, then reboot the servo to clear it.',
    requests: ({port, servo}) => [{cmd: 'fault.add', rule: {action: 'hardware_error', kind: 'overload', match: {port, servos: [servo]}}}],
  },
  low_voltage: {
    title: 'condition.set supply_voltage 1 V below the servo\'s Min Voltage Limit: Present Input Voltage reads low and the ' +
           'servo raises its Input Voltage Error where its Shutdown / Alarm settings select it. Set the supply back under Conditions.',
    requests: ({port, servo, minVoltage}) => [{cmd: 'condition.set', port, servo, supply_voltage: Math.max(0, Math.round(((minVoltage ?? 7) - 1) * 10) / 10)}],
  },
  drop_replies: {
    title: 'fault.add drop_reply: every status from the servo is lost on the way back (a broken return line); the ' +
           'controller times out. Edit the rule\'s "probability" (e.g. 0.05) for an intermittent contact.',
    requests: ({port, servo}) => [{cmd: 'fault.add', rule: {action: 'drop_reply', match: {port, servos: [servo]}}}],
  },
  corrupt_replies: {
    title: 'fault.add corrupt_crc: every status from the servo arrives with a wrong CRC or checksum (electrical noise); ' +
           'the controller must reject it. Edit the rule\'s "probability" (e.g. 0.05) for occasional noise.',
    requests: ({port, servo}) => [{cmd: 'fault.add', rule: {action: 'corrupt_crc', match: {port, servos: [servo]}}}],
  },
  slow_servo: {
    title: 'fault.add slow 5000 µs: the servo takes 5 ms longer over every packet (busy firmware), so its statuses and the ' +
           'Sync/Bulk Read chain after it come late; a tight timeout misses them.',
    requests: ({port, servo}) => [{cmd: 'fault.add', rule: {action: 'slow', us: 5000, match: {port, servos: [servo]}}}],
  },
  unplug: {
    title: 'servo.detach: the servo\'s cable is pulled (power and data): it answers nothing and its shaft is free. ' +
           'Replug it from the Control table view (or servo.attach).',
    requests: ({port, servo}) => [{cmd: 'servo.detach', port, servo}],
  },
};

function target() {
  const value = $('fault-servo').value;
  return value ? parseServoKey(value) : null;
}

async function applyPreset(name) {
  const preset = kPresets[name];
  const t = target();
  if (!preset || !t) {
    showMessage($('fault-message'), 'choose a servo first', false);
    return;
  }
  const model = servos.servos().find((s) => s.port === t.port && s.id === t.servo)?.model ?? '';
  let minVoltage = null;
  if (name === 'low_voltage') {
    try {
      minVoltage = (await servos.info(t.port, t.servo, model))?.minVoltage ?? null;
    } catch (error) {
      // The default below.
    }
  }
  const requests = preset.requests({...t, minVoltage});
  const shown = requests.find((r) => r.cmd === 'fault.add');
  if (shown) $('fault-json').value = JSON.stringify(shown.rule);
  const said = [];
  for (const req of requests) {
    const reply = await api.request(req);
    if (!reply.ok) {
      showMessage($('fault-message'), reply.error, false);
      return;
    }
    if (req.cmd === 'fault.add') said.push(`rule ${reply.result.rule} added`);
    else if (req.cmd === 'condition.set') {
      said.push(`supply ${num(reply.result.supply_voltage)} V on ${t.port}/${t.servo}` +
                (minVoltage !== null ? ` (its low voltage limit: ${num(minVoltage)} V)` : ''));
    } else if (req.cmd === 'servo.detach') said.push(`${t.port}/${t.servo} unplugged`);
    else said.push(`${req.cmd}: ${JSON.stringify(reply.result)}`);
  }
  showMessage($('fault-message'), `${name}: ${said.join('; ')}`, true);
  await pollRules();
}

async function addRule() {
  let rule;
  try {
    rule = JSON.parse($('fault-json').value);
  } catch (error) {
    showMessage($('fault-message'), `not valid JSON: ${error.message}`, false);
    return;
  }
  // Accept either the rule or a whole request {"cmd":"fault.add","rule":{...}}.
  if (rule && typeof rule === 'object' && rule.rule && !rule.action) rule = rule.rule;
  const reply = await api.request({cmd: 'fault.add', rule});
  showMessage($('fault-message'), reply.ok ? `rule ${reply.result.rule} added` : reply.error, reply.ok);
  await pollRules();
}

async function applyConditions() {
  const t = target();
  if (!t) return;
  const args = {port: t.port, servo: t.servo};
  const number = (id, key) => {
    const text = $(id).value.trim();
    if (text !== '') args[key] = Number(text);
  };
  number('cond-ambient', 'ambient_temperature');
  number('cond-voltage', 'supply_voltage');
  number('cond-load', 'external_load');
  args.blocked = $('cond-blocked').checked;
  const reply = await api.request({cmd: 'condition.set', ...args});
  if (reply.ok) {
    const r = reply.result;
    showMessage($('cond-message'), `${t.port}/${t.servo}: ambient ${r.ambient_temperature} °C, supply ${r.supply_voltage} V, ` +
      `load ${r.external_load} N·m, ${r.blocked ? 'blocked' : 'free'}`, true);
  } else {
    showMessage($('cond-message'), reply.error, false);
  }
}

async function loadScenario() {
  let scenario;
  try {
    scenario = JSON.parse($('scenario-json').value);
  } catch (error) {
    showMessage($('scenario-message'), `not valid JSON: ${error.message}`, false);
    return;
  }
  const reply = await api.request({cmd: 'scenario.load', scenario});
  showMessage($('scenario-message'), reply.ok
    ? `scenario ${reply.result.scenario ?? ''} loaded: ${reply.result.steps} steps`.replace('  ', ' ')
    : reply.error, reply.ok);
  await pollScenarios();
}

// {"port":"arm","servos":[3]} as "port=arm servos=3": dense, and still the API's names.
function pairs(object) {
  const text = Object.entries(object ?? {}).map(([key, value]) =>
    `${key}=${Array.isArray(value) ? value.join(',') : typeof value === 'object' ? JSON.stringify(value) : value}`);
  return text.join(' ');
}

function renderRules(rules) {
  const body = $('fault-list').tBodies[0];
  const rows = rules.map((entry) => {
    const {action, match, ...rest} = entry.rule ?? {};
    return el('tr', {dataset: {rule: String(entry.id)}, class: entry.active ? 'active' : 'inactive'},
      el('td', {class: 'num'}, entry.id),
      el('td', {}, action ?? ''),
      el('td', {class: 'mono', title: JSON.stringify(match ?? {})}, pairs(match) || 'all'),
      el('td', {class: 'mono', title: JSON.stringify(entry.rule ?? {})}, pairs(rest)),
      el('td', {class: 'num'}, entry.matched),
      el('td', {class: 'num'}, entry.fired),
      el('td', {}, entry.active ? 'yes' : 'no'),
      el('td', {}, el('button', {type: 'button', class: 'fault-remove', dataset: {rule: String(entry.id)}, title: 'fault.remove'}, 'remove')));
  });
  const signature = JSON.stringify(rules);
  if (body.dataset.signature !== signature) {
    body.dataset.signature = signature;
    body.replaceChildren(...rows);
  }
  if (!rules.length && !body.rows.length) body.append(el('tr', {class: 'empty'}, el('td', {colspan: '8'}, 'no rules')));
}

function renderScenarios(list) {
  const body = $('scenario-list').tBodies[0];
  const signature = JSON.stringify(list);
  if (body.dataset.signature === signature) return;
  body.dataset.signature = signature;
  body.replaceChildren(...list.map((s) => el('tr', {dataset: {scenario: String(s.scenario)}, class: s.done >= s.steps ? 'finished' : ''},
    el('td', {class: 'num'}, s.scenario),
    el('td', {class: 'mono'}, s.origin ?? ''),
    el('td', {}, el('progress', {max: String(Math.max(1, s.steps)), value: String(s.done ?? 0)})),
    el('td', {class: 'num'}, s.steps),
    el('td', {class: 'num'}, s.done),
    el('td', {class: 'num'}, s.failed ?? 0),
    el('td', {class: 'num'}, s.next_at_ms === null || s.next_at_ms === undefined ? '—' : fmt(s.next_at_ms, 1)),
    el('td', {class: 'num'}, typeof s.loaded_at_ms === 'number' ? fmt(s.loaded_at_ms, 1) : ''))));
  if (!list.length) body.append(el('tr', {class: 'empty'}, el('td', {colspan: '8'}, 'no scenarios loaded')));
}

async function pollRules() {
  renderRules(await api.call('fault.list'));
}

let scenarioListMissing = false;
async function pollScenarios() {
  if (scenarioListMissing) return;
  const reply = await api.request({cmd: 'scenario.list'}, {quiet: true});
  if (reply.ok) renderScenarios(reply.result);
  else if (/^unknown command/.test(reply.error ?? '')) {
    scenarioListMissing = true;
    $('scenario-list').tBodies[0].replaceChildren(el('tr', {}, el('td', {colspan: '8'}, 'this daemon has no scenario.list')));
  }
}

async function poll() {
  const listing = servos.refresh().then(() => fillSelect($('fault-servo'), servos.servoOptions()));
  await Promise.all([listing, pollRules(), pollScenarios()]);
}

function init() {
  for (const button of document.querySelectorAll('button[data-preset]')) {
    button.title = kPresets[button.dataset.preset]?.title ?? '';
    button.addEventListener('click', () => applyPreset(button.dataset.preset).catch(() => {}));
  }
  $('fault-add').addEventListener('click', () => addRule().catch(() => {}));
  $('fault-clear').addEventListener('click', async () => {
    const reply = await api.request({cmd: 'fault.clear'});
    showMessage($('fault-message'), reply.ok ? `${reply.result.removed} rules removed` : reply.error, reply.ok);
    await pollRules();
  });
  $('fault-list').addEventListener('click', async (event) => {
    const button = event.target.closest('button.fault-remove');
    if (!button) return;
    const reply = await api.request({cmd: 'fault.remove', rule: Number(button.dataset.rule)});
    showMessage($('fault-message'), reply.ok ? `rule ${reply.result.rule} removed` : reply.error, reply.ok);
    await pollRules();
  });
  $('cond-apply').addEventListener('click', () => applyConditions().catch(() => {}));
  $('scenario-load').addEventListener('click', () => loadScenario().catch(() => {}));
  setText($('fault-message'), '');
}

export default {
  name: 'faults',
  periodMs: 250,
  init,
  poll,
  connected: () => { scenarioListMissing = false; },
};
