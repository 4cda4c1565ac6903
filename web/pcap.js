// A pcap capture of trace records, laid out as `dxlemu run --pcap` writes one (docs/pcap.md):
// classic pcap, magic a1b2c3d4 written little-endian, version 2.4, microsecond timestamps,
// snap length 262144, link type LINKTYPE_USER0 (147); each record is a 4-byte pseudo-header
// [layout 1, direction, protocol, port index] and the bytes as on the wire.
//
// Timestamps: the daemon writes its start time on the wall clock plus simulated time; the page
// does not know when the daemon started, so a record's timestamp here is its simulated time `t`
// counted from the epoch (1970-01-01 00:00:00 plus t seconds). Wireshark's relative times are
// the same either way.

const kLinkTypeUser0 = 147;
const kSnapLength = 262144;

function protocolByte(protocol) {
  if (protocol === 1 || protocol === 2) return protocol;
  if (protocol === 'feetech') return 0x46;
  if (protocol === 'modbus') return 10;  // the Protocol Type value, as --pcap writes it
  return 0;
}

function bytesOf(hex) {
  const parts = hex.trim().split(/\s+/).filter(Boolean);
  const bytes = new Uint8Array(parts.length);
  parts.forEach((part, i) => { bytes[i] = Number.parseInt(part, 16); });
  return bytes;
}

/** The capture of `records` (trace records; those without `hex`, framing problems the trace
 *  describes without their bytes, are left out). portIndex(name) gives the pseudo-header's
 *  port byte. */
export function buildPcap(records, portIndex) {
  const packets = [];
  let total = 24;
  for (const record of records) {
    if (typeof record.hex !== 'string') continue;
    const data = bytesOf(record.hex);
    packets.push({record, data});
    total += 16 + 4 + data.length;
  }
  const buffer = new ArrayBuffer(total);
  const view = new DataView(buffer);
  const out = new Uint8Array(buffer);
  view.setUint32(0, 0xa1b2c3d4, true);
  view.setUint16(4, 2, true);
  view.setUint16(6, 4, true);
  view.setInt32(8, 0, true);   // thiszone
  view.setUint32(12, 0, true); // sigfigs
  view.setUint32(16, kSnapLength, true);
  view.setUint32(20, kLinkTypeUser0, true);
  let at = 24;
  for (const {record, data} of packets) {
    // `t` has ns resolution: round to the ns, then cut below the microsecond, as the daemon does.
    const micros = Math.max(0, Math.floor(Math.round((Number(record.t) || 0) * 1e9) / 1000));
    const length = 4 + data.length;
    view.setUint32(at, Math.floor(micros / 1e6), true);
    view.setUint32(at + 4, micros % 1e6, true);
    view.setUint32(at + 8, length, true);
    view.setUint32(at + 12, length, true);
    out[at + 16] = 1;
    out[at + 17] = record.dir === 'out' ? 1 : 0;
    out[at + 18] = protocolByte(record.protocol);
    out[at + 19] = portIndex(record.port);
    out.set(data, at + 20);
    at += 16 + length;
  }
  return out;
}
