// Small DOM and formatting helpers shared by the views.

/** The element with this id (throws when the page lacks it: a typo should fail loudly). */
export function $(id) {
  const element = document.getElementById(id);
  if (!element) throw new Error(`no element #${id}`);
  return element;
}

/** A new element: el('td', {class: 'raw', dataset: {key: 'id'}}, 'text', child, ...). */
export function el(tag, attrs = {}, ...children) {
  const element = document.createElement(tag);
  for (const [name, value] of Object.entries(attrs)) {
    if (value === undefined || value === null || value === false) continue;
    if (name === 'class') element.className = value;
    else if (name === 'dataset') Object.assign(element.dataset, value);
    else if (name.startsWith('on')) element.addEventListener(name.slice(2), value);
    else if (name in element && typeof value !== 'string') element[name] = value;
    else element.setAttribute(name, value === true ? '' : value);
  }
  for (const child of children) {
    if (child === undefined || child === null || child === false) continue;
    element.append(child instanceof Node ? child : String(child));
  }
  return element;
}

/** Text safe to put inside innerHTML. */
export function escapeHtml(text) {
  return String(text).replace(/[&<>"']/g, (c) => `&#${c.charCodeAt(0)};`);
}

/** Sets an element's text only when it changed (keeps selections and avoids layout work). */
export function setText(element, text) {
  const value = text === undefined || text === null ? '' : String(text);
  if (element.textContent !== value) element.textContent = value;
}

/** A message line under a form: ok (green) or refused (red), with the API's text verbatim. */
export function showMessage(element, text, ok) {
  setText(element, text);
  element.classList.toggle('ok', !!ok);
  element.classList.toggle('error', !ok && !!text);
}

/** Fills a <select> with [value, label] pairs, keeping the selection when it is still offered. */
export function fillSelect(select, options, keep = true) {
  const previous = select.value;
  const signature = JSON.stringify(options);
  if (select.dataset.signature === signature) return;
  select.dataset.signature = signature;
  select.replaceChildren(...options.map(([value, label]) => el('option', {value}, label)));
  if (keep && options.some(([value]) => value === previous)) select.value = previous;
}

/** Offers text as a file to download. */
export function download(name, data, type = 'text/plain') {
  const blob = data instanceof Blob ? data : new Blob([data], {type});
  const url = URL.createObjectURL(blob);
  const link = el('a', {href: url, download: name});
  document.body.append(link);
  link.click();
  link.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
}

/** Downloads a data: URL (a canvas's PNG). */
export function downloadUrl(name, url) {
  const link = el('a', {href: url, download: name});
  document.body.append(link);
  link.click();
  link.remove();
}

/** A file-name-safe timestamp for downloads. */
export function stamp() {
  return new Date().toISOString().replace(/[:.]/g, '-').slice(0, 19);
}

/** "port/id" for a servo, as the selects' values. */
export function servoKey(port, id) {
  return `${port}/${id}`;
}

/** {port, servo} from a "port/id" value. */
export function parseServoKey(key) {
  const slash = key.lastIndexOf('/');
  return {port: key.slice(0, slash), servo: Number(key.slice(slash + 1))};
}

/** A number for display: integers as they are, others to `digits` decimals. */
export function fmt(value, digits = 3) {
  if (value === undefined || value === null) return '';
  if (typeof value === 'boolean') return value ? 'yes' : 'no';
  if (typeof value !== 'number') return String(value);
  if (Number.isInteger(value)) return String(value);
  const text = value.toFixed(digits);
  return /^-0\.?0*$/.test(text) ? text.slice(1) : text;  // no "-0.0" for a tiny negative
}

/** A measured value for display: at most `digits` decimals, without trailing zeros
 *  (7.4, 3321.5, 100.005, 2048). */
export function num(value, digits = 3) {
  if (typeof value !== 'number' || !Number.isFinite(value)) return value === undefined || value === null ? '' : String(value);
  const scale = 10 ** digits;
  const rounded = Math.round(value * scale) / scale;
  return String(Object.is(rounded, -0) ? 0 : rounded);
}

/** Parses "12", "-3", "0x1F" as an integer; null when it is not one. */
export function parseInteger(text) {
  const trimmed = String(text).trim();
  if (/^[-+]?\d+$/.test(trimmed)) return Number(trimmed);
  if (/^0x[0-9a-f]+$/i.test(trimmed)) return Number.parseInt(trimmed, 16);
  return null;
}

/** Parses a control-table unit of one figure and one unit, "0.229 [rev/min]", "58,000 [rev/min²]"
 *  or the FEETECH files' "0.1V", "6.5mA": {factor, unit}; null for other forms ("R",
 *  "214.577 [rev/min²] / 1 [ms]"). */
export function parseUnit(text) {
  if (typeof text !== 'string') return null;
  const match = /^\s*(-?(?:\d{1,3}(?:,\d{3})+(?:\.\d+)?|\d*\.?\d+))\s*(?:\[([^\]\[]+)\]|([^\d\s\[\]/][^\[\]/]*))\s*$/.exec(text);
  if (!match) return null;
  const factor = Number(match[1].replace(/,/g, ''));
  return Number.isFinite(factor) ? {factor, unit: (match[2] ?? match[3]).trim()} : null;
}

/** Resolves after ms milliseconds. */
export function sleep(ms) {
  return new Promise((resolve) => setTimeout(resolve, ms));
}
