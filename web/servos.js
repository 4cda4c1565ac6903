// What the views share about the bus: the latest `list`, and each servo's control table layout
// (from `table`, or item by item with `get` where the daemon has no `table`).
import * as api from './api.js';
import {parseUnit, servoKey} from './util.js';

let latest = {ports: []};
let tableSupported = null;  // null: not asked yet
const infos = new Map();     // "port/id/model" -> {at, value, loading}
const kInfoMaxAgeMs = 5000;

/** The last `list` result. */
export function list() {
  return latest;
}

/** Asks `list` again and keeps its result. */
export async function refresh() {
  latest = await api.call('list');
  return latest;
}

/** Every servo as {port, id, model, key, label, ...list fields}. */
export function servos() {
  const all = [];
  for (const port of latest.ports ?? []) {
    for (const servo of port.servos ?? []) {
      all.push({...servo, port: port.name, key: servoKey(port.name, servo.id),
                label: `${port.name} / ${servo.id} (${servo.model})`});
    }
  }
  return all;
}

/** [value, label] pairs of every servo, for a <select>. */
export function servoOptions() {
  return servos().map((s) => [s.key, s.label]);
}

/** A port's position in the list (the pcap pseudo-header's port index), or 255. */
export function portIndex(name) {
  const index = (latest.ports ?? []).findIndex((port) => port.name === name);
  return index < 0 || index > 255 ? 255 : index;
}

/** Whether the daemon answers `table` (known after the first table() call). */
export function hasTable() {
  return tableSupported !== false;
}

/** The `table` result of a servo, or null when the daemon has no `table` command. */
export async function table(port, servo, options = {}) {
  if (tableSupported === false) return null;
  const reply = await api.request({cmd: 'table', port, servo}, {quiet: true, ...options});
  if (reply.ok) {
    tableSupported = true;
    return reply.result;
  }
  if (/^unknown command/.test(reply.error ?? '')) {
    tableSupported = false;
    return null;
  }
  throw new api.ApiError(reply.error, reply);
}

const kVoltageKeys = ['present_input_voltage', 'present_voltage'];
const kTemperatureLimitKeys = ['temperature_limit', 'maximum_temperature_limit', 'motor_temperature_limit'];
const kMinVoltageKeys = ['min_voltage_limit', 'minimum_input_voltage'];

/** What the bus view and the presets need of a servo beyond `list`: firmware text, the key and
 *  scale of its supply voltage item, its temperature limit (raw, °C), its low voltage limit (V),
 *  its item keys. Returns what is known now (undefined at first) and asks again in the
 *  background when that is older than a few seconds, so a poll never waits for it. */
export function infoNow(port, id, model) {
  const entry = entryOf(port, id, model);
  return entry.value;
}

/** info as infoNow, but waits for it when nothing is known yet. */
export async function info(port, id, model) {
  const entry = entryOf(port, id, model);
  return entry.value ?? entry.loading;
}

function entryOf(port, id, model) {
  const key = `${servoKey(port, id)}/${model}`;
  let entry = infos.get(key);
  if (!entry) {
    entry = {at: -Infinity, value: undefined, loading: null};
    infos.set(key, entry);
  }
  if (!entry.loading && performance.now() - entry.at > kInfoMaxAgeMs && api.isConnected()) {
    entry.at = performance.now();
    entry.loading = loadInfo(port, id).then((value) => {
      entry.value = value;
      return value;
    }, () => entry.value).finally(() => { entry.loading = null; });
  }
  return entry;
}

async function loadInfo(port, id) {
  const t = await table(port, id);
  let result;
  if (t) {
    const items = new Map(t.items.map((item) => [item.key, item]));
    const pick = (keys) => keys.map((k) => items.get(k)).find(Boolean);
    const voltage = pick(kVoltageKeys);
    const limit = pick(kTemperatureLimitKeys);
    const minVoltage = pick(kMinVoltageKeys);
    result = {
      firmware: firmwareText(items.get('firmware_version')?.value, items.get('firmware_major_version')?.value,
                             items.get('firmware_minor_version')?.value),
      voltageKey: voltage?.key ?? null,
      voltageScale: parseUnit(voltage?.unit)?.factor ?? 0.1,
      temperatureLimit: limit?.value ?? null,
      minVoltage: minVoltage ? minVoltage.value * (parseUnit(minVoltage.unit)?.factor ?? 0.1) : null,
      keys: t.items.map((item) => item.key),
      table: t,
    };
  } else {
    const get = async (item) => {
      const reply = await api.request({cmd: 'get', port, servo: id, item}, {quiet: true});
      return reply.ok ? reply.result.value : undefined;
    };
    const first = async (keys) => {
      for (const k of keys) {
        const value = await get(k);
        if (value !== undefined) return {key: k, value};
      }
      return null;
    };
    const [fw, major, minor] = [await get('firmware_version'), await get('firmware_major_version'),
                                await get('firmware_minor_version')];
    const voltage = await first(kVoltageKeys);
    const limit = await first(kTemperatureLimitKeys);
    const minVoltage = await first(kMinVoltageKeys);
    result = {firmware: firmwareText(fw, major, minor), voltageKey: voltage?.key ?? null, voltageScale: 0.1,
              temperatureLimit: limit?.value ?? null, minVoltage: minVoltage ? minVoltage.value * 0.1 : null,
              keys: null, table: null};
  }
  return result;
}

function firmwareText(version, major, minor) {
  if (version !== undefined && version !== null) return String(version);
  if (major !== undefined && major !== null) return `${major}.${minor ?? 0}`;
  return '';
}

/** Forgets every cached servo layout (after a factory reset, a new ID, a reconnect). */
export function forget() {
  infos.clear();
}
