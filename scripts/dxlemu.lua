-- dxlemu.lua: a Wireshark dissector for the captures of `dxlemu run --pcap FILE` (docs/pcap.md).
--
--   wireshark -X lua_script:scripts/dxlemu.lua capture.pcap
--   tshark -X lua_script:scripts/dxlemu.lua -r capture.pcap -V
--
-- or copy this file to Wireshark's personal Lua plugins folder (Help > About > Folders).
--
-- A record is link type LINKTYPE_USER0 (147): a 4-byte pseudo-header (version, direction,
-- protocol, port index) and the bytes on the line. The bytes are decoded as DYNAMIXEL Protocol 1.0
-- (FF FF ID LEN INST ... checksum) and 2.0 (FF FF FD 00 ID LEN_L LEN_H INST ... CRC-16, byte
-- stuffing) packets, several per record if need be, with bytes outside any packet shown as
-- garbage. Client-to-servos packets are instructions, servos-to-client packets are statuses.
-- Records of a FEETECH port (pseudo-header protocol 0x46) are decoded as FEETECH's FT-SCS packets:
-- the 1.0 layout with FEETECH's instruction set and status bits. A record of a Modbus RTU port
-- (pseudo-header protocol 10) is one Modbus RTU frame (silence-delimited: one frame per record):
-- server address, function, its fields, exception code, CRC-16/MODBUS.
-- Field names: dxlemu.* for the pseudo-header, dxl.* for the packets of the protocol "dynamixel",
-- feetech.* for those of the protocol "feetech", modbus_rtu.* for those of the protocol
-- "modbus_rtu" (docs/pcap.md lists them).

local bitops = bit32 or bit -- Lua 5.2's bit32, or the BitOp library of other Wireshark builds
local band, bxor, lshift, rshift = bitops.band, bitops.bxor, bitops.lshift, bitops.rshift

local PSEUDO_HEADER_BYTES = 4
local FEETECH = 0x46 -- the pseudo-header's protocol byte of a FEETECH port
local MODBUS = 10 -- the pseudo-header's protocol byte of a Modbus RTU port (Protocol Type 10)
local PSEUDO_HEADER_VERSION = 1
local TO_SERVOS, TO_CLIENT = 0, 1

local V1_HEADER = "\255\255"
local V2_HEADER = "\255\255\253\0"
local V2_FIXED = 7 -- FF FF FD 00 ID LEN_L LEN_H
local V1_FIXED = 4 -- FF FF ID LEN
local V2_MIN_LENGTH = 3 -- instruction + CRC (protocol2.md "Length")
local V1_MIN_LENGTH = 2 -- instruction + checksum (protocol1.md "Length")
local INVALID_ID = 0xFF
local BROADCAST_ID = 0xFE
local STATUS = 0x55

local PING, READ, WRITE, REG_WRITE = 0x01, 0x02, 0x03, 0x04
local SYNC_READ, SYNC_WRITE, FAST_SYNC_READ = 0x82, 0x83, 0x8A
local BULK_READ, BULK_WRITE, FAST_BULK_READ = 0x92, 0x93, 0x9A

local instruction_names = {
  [PING] = "Ping", [READ] = "Read", [WRITE] = "Write", [REG_WRITE] = "Reg Write",
  [0x05] = "Action", [0x06] = "Factory Reset", [0x08] = "Reboot", [0x10] = "Clear",
  [0x20] = "Control Table Backup", [STATUS] = "Status", [SYNC_READ] = "Sync Read",
  [SYNC_WRITE] = "Sync Write", [FAST_SYNC_READ] = "Fast Sync Read", [BULK_READ] = "Bulk Read",
  [BULK_WRITE] = "Bulk Write", [FAST_BULK_READ] = "Fast Bulk Read",
}
-- protocol2.md "Error": bits 6 ~ 0.
local error_numbers = {
  [0] = "None", [1] = "Result Fail", [2] = "Instruction Error", [3] = "CRC Error",
  [4] = "Data Range Error", [5] = "Data Length Error", [6] = "Data Limit Error",
  [7] = "Access Error",
}
local checksum_status = { [0] = "Bad", [1] = "Good" }
-- FEETECH's FT-SCS instruction set (protocol-ft-scs.md "Instruction types").
local feetech_instruction_names = {
  [PING] = "Ping", [READ] = "Read", [WRITE] = "Write", [REG_WRITE] = "Reg Write",
  [0x05] = "Action", [0x06] = "Parameter Recovery", [0x08] = "Restart",
  [0x09] = "Parameter Backup", [0x0A] = "Status Reset", [0x0B] = "Position Calibration",
  [SYNC_READ] = "Sync Read", [SYNC_WRITE] = "Sync Write",
}

-- Modbus RTU (modbus-rtu.md): address 0 is broadcast; a frame is address, function, data, CRC.
local MODBUS_BROADCAST = 0
local MODBUS_MIN_FRAME = 4
local MODBUS_EXCEPTION_FLAG = 0x80
local READ_HOLDING_REGISTERS, READ_INPUT_REGISTERS = 0x03, 0x04
local WRITE_SINGLE_REGISTER, DIAGNOSTICS = 0x06, 0x08
local WRITE_MULTIPLE_REGISTERS, READ_WRITE_MULTIPLE_REGISTERS = 0x10, 0x17
local modbus_function_names = {
  [READ_HOLDING_REGISTERS] = "Read Holding Registers",
  [READ_INPUT_REGISTERS] = "Read Input Registers",
  [WRITE_SINGLE_REGISTER] = "Write Single Register",
  [DIAGNOSTICS] = "Diagnostics",
  [WRITE_MULTIPLE_REGISTERS] = "Write Multiple Registers",
  [READ_WRITE_MULTIPLE_REGISTERS] = "Read/Write Multiple Registers",
}
-- modbus-rtu.md "Exception responses".
local modbus_exception_names = {
  [0x01] = "Illegal Function", [0x02] = "Illegal Data Address", [0x03] = "Illegal Data Value",
  [0x04] = "Server Device Failure", [0x06] = "Server Device Busy",
}

-- Protocol 2.0 CRC-16: polynomial 0x8005, initial value 0, MSB first, no reflection
-- (protocol2-crc.md; the same table as emulator/wire/crc16.cpp).
local crc_table = {}
for i = 0, 255 do
  local crc = lshift(i, 8)
  for _ = 1, 8 do
    if band(crc, 0x8000) ~= 0 then
      crc = bxor(lshift(crc, 1), 0x8005)
    else
      crc = lshift(crc, 1)
    end
    crc = band(crc, 0xFFFF)
  end
  crc_table[i] = crc
end

local function crc16(bytes)
  local crc = 0
  for i = 1, #bytes do
    crc = band(bxor(lshift(crc, 8), crc_table[band(bxor(rshift(crc, 8), bytes:byte(i)), 0xFF)]),
               0xFFFF)
  end
  return crc
end

-- CRC-16/MODBUS: polynomial 0xA001 (0x8005 reflected), initial value 0xFFFF, no final XOR.
local function crc16_modbus(bytes)
  local crc = 0xFFFF
  for i = 1, #bytes do
    crc = bxor(crc, bytes:byte(i))
    for _ = 1, 8 do
      if band(crc, 1) ~= 0 then
        crc = bxor(rshift(crc, 1), 0xA001)
      else
        crc = rshift(crc, 1)
      end
    end
  end
  return crc
end

-- Protocol 1.0 checksum: ~(ID + LENGTH + INSTRUCTION + PARAMETERS) & 0xFF.
local function checksum1(bytes)
  local sum = 0
  for i = 1, #bytes do
    sum = sum + bytes:byte(i)
  end
  return 255 - sum % 256
end

-- Removes Protocol 2.0 byte stuffing (FF FF FD FD -> FF FF FD, protocol2.md "Packet Process");
-- returns the bytes as a table and whether anything was removed.
local function unstuff(bytes)
  local out, i, stuffed = {}, 1, false
  while i <= #bytes do
    if bytes:sub(i, i + 3) == "\255\255\253\253" then
      for _, byte in ipairs({ 0xFF, 0xFF, 0xFD }) do
        out[#out + 1] = byte
      end
      i, stuffed = i + 4, true
    else
      out[#out + 1] = bytes:byte(i)
      i = i + 1
    end
  end
  return out, stuffed
end

local capture = Proto("dxlemu", "dxlemu capture")
-- The filter name "dxl" belongs to Wireshark's Data Exchange Layer dissector, so the protocol is
-- "dynamixel"; its fields keep the short dxl.* names (none of them is a Data Exchange Layer field).
local dxl = Proto("dynamixel", "DYNAMIXEL")

local hf = {
  version = ProtoField.uint8("dxlemu.version", "Pseudo-header version", base.DEC),
  direction = ProtoField.uint8("dxlemu.direction", "Direction", base.DEC,
                               { [TO_SERVOS] = "client to servos", [TO_CLIENT] = "servos to client" }),
  protocol = ProtoField.uint8("dxlemu.protocol", "Protocol", base.DEC,
                              { [0] = "unknown", [1] = "1.0", [2] = "2.0", [FEETECH] = "feetech",
                                [MODBUS] = "modbus" }),
  port = ProtoField.uint8("dxlemu.port", "Port index", base.DEC),
}
capture.fields = { hf.version, hf.direction, hf.protocol, hf.port }

-- The packet fields DYNAMIXEL's and FEETECH's protocols share, under `prefix` ("dxl" or
-- "feetech"); `wide` gives LENGTH, address and data length two bytes (DYNAMIXEL 2.0's widths).
local function packet_fields(prefix, wide, names)
  local number = wide and ProtoField.uint16 or ProtoField.uint8
  return {
    type = ProtoField.uint8(prefix .. ".packet_type", "Packet type", base.DEC,
                            { [0] = "Instruction", [1] = "Status" }),
    header = ProtoField.bytes(prefix .. ".header", "Header"),
    id = ProtoField.uint8(prefix .. ".id", "Packet ID", base.DEC),
    length = number(prefix .. ".length", "Length", base.DEC),
    instruction = ProtoField.uint8(prefix .. ".instruction", "Instruction", base.HEX, names),
    params = ProtoField.bytes(prefix .. ".params", "Parameters"),
    address = number(prefix .. ".address", "Address", base.DEC),
    data_length = number(prefix .. ".data_length", "Data length", base.DEC),
    data = ProtoField.bytes(prefix .. ".data", "Data"),
    target_id = ProtoField.uint8(prefix .. ".target_id", "Target ID", base.DEC),
    checksum = ProtoField.uint8(prefix .. ".checksum", "Checksum", base.HEX),
    checksum_status = ProtoField.uint8(prefix .. ".checksum.status", "Checksum status", base.DEC,
                                       checksum_status),
  }
end

-- Registers every field of `fields` with `proto`.
local function register(proto, fields)
  proto.fields = {}
  for _, field in pairs(fields) do
    proto.fields[#proto.fields + 1] = field
  end
end

local f = packet_fields("dxl", true, instruction_names)
f.protocol = ProtoField.uint8("dxl.protocol", "Protocol", base.DEC, { [1] = "1.0", [2] = "2.0" })
f.error = ProtoField.uint8("dxl.error", "Error", base.HEX)
f.alert = ProtoField.bool("dxl.error.alert", "Alert (hardware error)", 8, nil, 0x80)
f.error_number = ProtoField.uint8("dxl.error.number", "Error number", base.DEC, error_numbers, 0x7F)
-- protocol1.md "Status Packet": one bit per error.
f.e1_instruction = ProtoField.bool("dxl.error.instruction", "Instruction Error", 8, nil, 0x40)
f.e1_overload = ProtoField.bool("dxl.error.overload", "Overload Error", 8, nil, 0x20)
f.e1_checksum = ProtoField.bool("dxl.error.checksum", "Checksum Error", 8, nil, 0x10)
f.e1_range = ProtoField.bool("dxl.error.range", "Range Error", 8, nil, 0x08)
f.e1_overheating = ProtoField.bool("dxl.error.overheating", "Overheating Error", 8, nil, 0x04)
f.e1_angle = ProtoField.bool("dxl.error.angle_limit", "Angle Limit Error", 8, nil, 0x02)
f.e1_voltage = ProtoField.bool("dxl.error.input_voltage", "Input Voltage Error", 8, nil, 0x01)
f.crc = ProtoField.uint16("dxl.crc", "CRC", base.HEX)
f.crc_status = ProtoField.uint8("dxl.crc.status", "CRC status", base.DEC, checksum_status)
f.garbage = ProtoField.bytes("dxl.garbage", "Bytes outside any packet")
f.truncated = ProtoField.bytes("dxl.truncated", "Incomplete packet")
register(dxl, f)

local feetech = Proto("feetech", "FEETECH")
-- FEETECH's packets: DYNAMIXEL 1.0's layout; the error byte holds FEETECH's servo status bits
-- (the memory tables' "Servo status").
local g = packet_fields("feetech", false, feetech_instruction_names)
g.error = ProtoField.uint8("feetech.error", "Error (servo status)", base.HEX)
g.e_overload = ProtoField.bool("feetech.error.overload", "Overload", 8, nil, 0x20)
g.e_current = ProtoField.bool("feetech.error.current", "Overcurrent", 8, nil, 0x08)
g.e_overheat = ProtoField.bool("feetech.error.overheat", "Overheat", 8, nil, 0x04)
g.e_angle = ProtoField.bool("feetech.error.angle_sensor", "Angle sensor (magnetic encoder)", 8,
                            nil, 0x02)
g.e_voltage = ProtoField.bool("feetech.error.voltage", "Voltage", 8, nil, 0x01)
register(feetech, g)

local ef = {
  bad_crc = ProtoExpert.new("dxl.crc.bad", "Bad CRC", expert.group.CHECKSUM, expert.severity.ERROR),
  bad_checksum = ProtoExpert.new("dxl.checksum.bad", "Bad checksum", expert.group.CHECKSUM,
                                 expert.severity.ERROR),
  truncated = ProtoExpert.new("dxl.truncated.expert", "Incomplete packet", expert.group.MALFORMED,
                              expert.severity.ERROR),
  garbage = ProtoExpert.new("dxl.garbage.expert", "Bytes outside any packet",
                            expert.group.PROTOCOL, expert.severity.WARN),
  status_error = ProtoExpert.new("dxl.error.expert", "Status reports an error",
                                 expert.group.RESPONSE_CODE, expert.severity.WARN),
  fast_reply = ProtoExpert.new("dxl.fast_reply", "Fast Sync/Bulk Read reply",
                               expert.group.PROTOCOL, expert.severity.NOTE),
  version = ProtoExpert.new("dxlemu.version.unknown", "Unknown pseudo-header version",
                            expert.group.UNDECODED, expert.severity.ERROR),
}
dxl.experts = { ef.bad_crc, ef.bad_checksum, ef.truncated, ef.garbage, ef.status_error, ef.fast_reply }
capture.experts = { ef.version }

-- What starts at `pos` of `buf` (`avail` bytes left): "v2" or "v1" with the packet's size, or
-- "partial" when a header starts there but the record ends first, or nil. `hint` is the
-- pseudo-header's protocol (0: try 2.0 first, then 1.0).
local function classify(buf, pos, avail, hint)
  local head = buf:raw(pos, math.min(avail, V2_FIXED))
  if hint ~= 1 and hint ~= FEETECH and V2_HEADER:sub(1, #head) == head:sub(1, 4) then
    if #head >= 5 and head:byte(5) == INVALID_ID then
      return nil
    end
    if #head < V2_FIXED then
      return "partial", avail
    end
    local length = head:byte(6) + 256 * head:byte(7)
    if length < V2_MIN_LENGTH then
      return nil
    end
    local total = V2_FIXED + length
    if total > avail then
      return "partial", avail
    end
    return "v2", total
  end
  if hint ~= 2 and V1_HEADER:sub(1, #head) == head:sub(1, 2) then
    if #head >= 3 and head:byte(3) == INVALID_ID then
      return nil
    end
    if #head < V1_FIXED then
      return "partial", avail
    end
    local length = head:byte(4)
    if length < V1_MIN_LENGTH then
      return nil
    end
    local total = V1_FIXED + length
    if total > avail then
      return "partial", avail
    end
    return hint == FEETECH and "feetech" or "v1", total
  end
  return nil
end

-- True when a complete packet starts somewhere after `pos`: then a header at `pos` that runs past
-- the record is noise, as the emulator's framer would find after rescanning.
local function complete_packet_after(buf, pos, len, hint)
  for p = pos + 1, len - 1 do
    local kind = classify(buf, p, len - p, hint)
    if kind == "v1" or kind == "v2" or kind == "feetech" then
      return true
    end
  end
  return false
end

-- The parameters as a TvbRange: the packet's own bytes, or a new data source when byte stuffing
-- was removed. nil when there are none.
local function params_range(buf, offset, bytes_table, stuffed, count)
  if count <= 0 then
    return nil
  end
  if not stuffed then
    return buf(offset, count)
  end
  local ba = ByteArray.new()
  ba:set_size(count)
  for i = 1, count do
    ba:set_index(i - 1, bytes_table[#bytes_table - count + i])
  end
  return ba:tvb("Unstuffed parameters")(0, count)
end

local function le(range)
  return range:le_uint()
end

-- Decodes an instruction's parameters under `tree` and returns a short text for the Info column.
-- `protocol` is 1, 2 or FEETECH; `f` the protocol's fields (DYNAMIXEL's or FEETECH's).
local function instruction_params(tree, p, protocol, instruction, f)
  local n = p and p:len() or 0
  local a = protocol == 2 and 2 or 1 -- address and length fields: 2 bytes in 2.0, 1 in 1.0
  local add = protocol == 2 and tree.add_le or tree.add
  local function field(fld, off, size)
    add(tree, fld, p(off, size))
    return le(p(off, size))
  end
  if (instruction == READ) and n >= 2 * a then
    local address = field(f.address, 0, a)
    local count = field(f.data_length, a, a)
    return string.format(" addr=%d len=%d", address, count)
  end
  if (instruction == WRITE or instruction == REG_WRITE) and n > a then
    local address = field(f.address, 0, a)
    tree:add(f.data_length, p(a, n - a), n - a):set_generated()
    tree:add(f.data, p(a, n - a))
    return string.format(" addr=%d len=%d", address, n - a)
  end
  if (instruction == SYNC_READ or (instruction == FAST_SYNC_READ and protocol ~= FEETECH)) and
     n >= 2 * a then
    local address = field(f.address, 0, a)
    local count = field(f.data_length, a, a)
    local ids = {}
    for off = 2 * a, n - 1 do
      tree:add(f.target_id, p(off, 1))
      ids[#ids + 1] = tostring(p(off, 1):uint())
    end
    return string.format(" addr=%d len=%d ids=%s", address, count, table.concat(ids, ","))
  end
  if instruction == SYNC_WRITE and n >= 2 * a then
    local address = field(f.address, 0, a)
    local count = field(f.data_length, a, a)
    local ids = {}
    local off = 2 * a
    while count > 0 and off + 1 + count <= n do
      local block = tree:add(f.target_id, p(off, 1))
      block:add(f.data, p(off + 1, count))
      ids[#ids + 1] = tostring(p(off, 1):uint())
      off = off + 1 + count
    end
    return string.format(" addr=%d len=%d ids=%s", address, count, table.concat(ids, ","))
  end
  if protocol ~= FEETECH and
     (instruction == BULK_READ or instruction == FAST_BULK_READ or instruction == BULK_WRITE) then
    -- 2.0: ID, address (2), length (2) [, data] per servo; 1.0 Bulk Read: 0x00, then length,
    -- ID, address per servo.
    local ids = {}
    local off = protocol == 2 and 0 or 1
    local block_size = protocol == 2 and 5 or 3
    while off + block_size <= n do
      local id_off = protocol == 2 and off or off + 1
      local block = tree:add(f.target_id, p(id_off, 1))
      local count
      if protocol == 2 then
        block:add_le(f.address, p(off + 1, 2))
        count = le(p(off + 3, 2))
        block:add_le(f.data_length, p(off + 3, 2))
      else
        count = p(off, 1):uint()
        block:add(f.data_length, p(off, 1))
        block:add(f.address, p(off + 2, 1))
      end
      ids[#ids + 1] = tostring(p(id_off, 1):uint())
      off = off + block_size
      if instruction == BULK_WRITE then
        if off + count > n then
          break
        end
        if count > 0 then
          block:add(f.data, p(off, count))
        end
        off = off + count
      end
    end
    return " ids=" .. table.concat(ids, ",")
  end
  return n > 0 and string.format(" params=%d bytes", n) or ""
end

-- Adds the error byte of a status (`range`) with its bits.
local function error_field(tree, range, protocol)
  local item = tree:add(protocol == FEETECH and g.error or f.error, range)
  if protocol == FEETECH then
    for _, fld in ipairs({ g.e_overload, g.e_current, g.e_overheat, g.e_angle, g.e_voltage }) do
      item:add(fld, range)
    end
  elseif protocol == 2 then
    item:add(f.alert, range)
    item:add(f.error_number, range)
  else
    for _, fld in ipairs({ f.e1_instruction, f.e1_overload, f.e1_checksum, f.e1_range,
                           f.e1_overheating, f.e1_angle, f.e1_voltage }) do
      item:add(fld, range)
    end
  end
  local value = range:uint()
  if value ~= 0 then
    item:add_proto_expert_info(ef.status_error, string.format("Status error 0x%02x", value))
  end
  return value
end

-- Dissects one complete packet of `total` bytes at `pos`; returns its Info text.
-- Marks a packet's check (CRC or checksum, shown by `item` over `range`) as good or bad, with an
-- expert note when it is bad; returns what the packet's one-line text gets (" [BAD CRC]" or "").
local function verify(item, tree, status_field, range, given, expected, expert, name, digits)
  tree:add(status_field, range, given == expected and 1 or 0):set_generated()
  if given == expected then
    return ""
  end
  item:append_text(string.format(" [incorrect, should be 0x" .. digits .. "]", expected))
  item:add_proto_expert_info(expert, string.format("Bad %s 0x" .. digits .. ", expected 0x" ..
                                                   digits, name, given, expected))
  return " [BAD " .. string.upper(name) .. "]"
end

local function dissect_packet(buf, pos, total, kind, direction, tree)
  local protocol = kind == "v2" and 2 or (kind == "feetech" and FEETECH or 1)
  -- FEETECH's packets have DYNAMIXEL 1.0's layout; only their fields and names differ.
  local fields = protocol == FEETECH and g or f
  local names = protocol == FEETECH and feetech_instruction_names or instruction_names
  local is_status = direction == TO_CLIENT
  local ptree = tree:add(protocol == FEETECH and feetech or dxl, buf(pos, total))
  local header = protocol == 2 and 4 or 2
  if protocol ~= FEETECH then
    ptree:add(f.protocol, buf(pos, header), protocol):set_generated()
  end
  ptree:add(fields.type, buf(pos, total), is_status and 1 or 0):set_generated()
  ptree:add(fields.header, buf(pos, header))
  local id = buf(pos + header, 1):uint()
  ptree:add(fields.id, buf(pos + header, 1))
  local check_size = protocol == 2 and 2 or 1
  local body = pos + header + 1 + (protocol == 2 and 2 or 1) -- the instruction byte
  if protocol == 2 then
    ptree:add_le(f.length, buf(pos + header + 1, 2))
  else
    ptree:add(fields.length, buf(pos + header + 1, 1))
  end
  local check_at = pos + total - check_size
  local text
  local role = is_status and "Status" or "Instruction"
  if protocol == 2 then
    local instruction = buf(body, 1):uint()
    ptree:add(f.instruction, buf(body, 1))
    local fast = is_status and id == BROADCAST_ID and instruction == STATUS
    -- Stuffing covers the instruction and parameters; Fast replies are never stuffed.
    local region = buf:raw(body, check_at - body)
    local bytes, stuffed = unstuff(region)
    if fast then
      bytes, stuffed = { region:byte(1, -1) }, false
    end
    local count = #bytes - 1
    local p = params_range(buf, body + 1, bytes, stuffed, count)
    if instruction == STATUS then
      text = string.format("%s id=%d", role, id)
    else
      text = string.format("%s id=%d %s", role, id, instruction_names[instruction]
                           or string.format("0x%02x", instruction))
    end
    if is_status then
      if p then
        local err = error_field(ptree, p(0, 1), 2)
        text = text .. string.format(" err=0x%02x", err)
        if count > 1 then
          ptree:add(f.params, p(1, count - 1))
          text = text .. string.format(" params=%d bytes", count - 1)
        end
      end
      if fast then
        ptree:add_proto_expert_info(ef.fast_reply,
          "Fast Sync/Bulk Read reply: its blocks (error, ID, data, CRC) are shown as parameters")
        text = text .. " (fast reply)"
      end
    elseif p then
      local ptree2 = ptree:add(f.params, p)
      text = text .. instruction_params(ptree2, p, 2, instruction, f)
    end
    local range = buf(check_at, 2)
    text = text .. verify(ptree:add_le(f.crc, range), ptree, f.crc_status, range, range:le_uint(),
                          crc16(buf:raw(pos, check_at - pos)), ef.bad_crc, "CRC", "%04x")
  else
    local count = check_at - body - 1
    if is_status then
      local err = error_field(ptree, buf(body, 1), protocol)
      text = string.format("%s id=%d err=0x%02x", role, id, err)
      if count > 0 then
        ptree:add(fields.params, buf(body + 1, count))
        text = text .. string.format(" params=%d bytes", count)
      end
    else
      local instruction = buf(body, 1):uint()
      ptree:add(fields.instruction, buf(body, 1))
      text = string.format("%s id=%d %s", role, id, names[instruction]
                           or string.format("0x%02x", instruction))
      if count > 0 then
        local p = buf(body + 1, count)
        local ptree2 = ptree:add(fields.params, p)
        text = text .. instruction_params(ptree2, p, protocol, instruction, fields)
      end
    end
    local range = buf(check_at, 1)
    text = text .. verify(ptree:add(fields.checksum, range), ptree, fields.checksum_status, range,
                          range:uint(), checksum1(buf:raw(pos + header, check_at - pos - header)),
                          ef.bad_checksum, "checksum", "%02x")
  end
  ptree:append_text(protocol == FEETECH and ", " .. text
                    or string.format(" %s.0, %s", protocol, text))
  return text
end

-- Modbus RTU frames (records of a Modbus port): filter name "modbus_rtu", since Wireshark's own
-- Modbus dissectors are "mbrtu" and "modbus". Wireshark 4.0's mbrtu cannot tell a serial
-- capture's request from its response when both look alike (Write Single Register, Diagnostics:
-- the response echoes the request), and checks no CRC by default; the record's direction says
-- which it is, so the frames are decoded here.
local modbus = Proto("modbus_rtu", "Modbus RTU (dxlemu)")
local m = {
  type = ProtoField.uint8("modbus_rtu.packet_type", "Packet type", base.DEC,
                          { [0] = "Request", [1] = "Response" }),
  address = ProtoField.uint8("modbus_rtu.address", "Server address", base.DEC),
  ["function"] = ProtoField.uint8("modbus_rtu.function", "Function code", base.HEX,
                                  modbus_function_names, 0x7F),
  exception = ProtoField.bool("modbus_rtu.exception", "Exception response", 8, nil,
                              MODBUS_EXCEPTION_FLAG),
  exception_code = ProtoField.uint8("modbus_rtu.exception_code", "Exception code", base.HEX,
                                    modbus_exception_names),
  subfunction = ProtoField.uint16("modbus_rtu.subfunction", "Sub-function", base.HEX,
                                  { [0] = "Return Query Data" }),
  start = ProtoField.uint16("modbus_rtu.start", "Starting register", base.DEC),
  quantity = ProtoField.uint16("modbus_rtu.quantity", "Quantity of registers", base.DEC),
  read_start = ProtoField.uint16("modbus_rtu.read_start", "Read starting register", base.DEC),
  read_quantity = ProtoField.uint16("modbus_rtu.read_quantity", "Quantity to read", base.DEC),
  write_start = ProtoField.uint16("modbus_rtu.write_start", "Write starting register", base.DEC),
  write_quantity = ProtoField.uint16("modbus_rtu.write_quantity", "Quantity to write", base.DEC),
  byte_count = ProtoField.uint8("modbus_rtu.byte_count", "Byte count", base.DEC),
  register = ProtoField.uint16("modbus_rtu.register", "Register", base.DEC),
  value = ProtoField.uint16("modbus_rtu.value", "Register value", base.DEC),
  table_address = ProtoField.uint16("modbus_rtu.table_address", "Control-table address",
                                    base.DEC),
  data = ProtoField.bytes("modbus_rtu.data", "Data"),
  crc = ProtoField.uint16("modbus_rtu.crc", "CRC", base.HEX),
  crc_status = ProtoField.uint8("modbus_rtu.crc.status", "CRC status", base.DEC,
                               checksum_status),
  truncated = ProtoField.bytes("modbus_rtu.truncated", "Incomplete frame"),
}
register(modbus, m)
local mx = {
  bad_crc = ProtoExpert.new("modbus_rtu.crc.bad", "Bad CRC", expert.group.CHECKSUM,
                            expert.severity.ERROR),
  exception = ProtoExpert.new("modbus_rtu.exception.expert", "Exception response",
                              expert.group.RESPONSE_CODE, expert.severity.WARN),
  malformed = ProtoExpert.new("modbus_rtu.malformed", "Data do not fit the function",
                              expert.group.MALFORMED, expert.severity.ERROR),
  truncated = ProtoExpert.new("modbus_rtu.truncated.expert", "Frame shorter than 4 bytes",
                              expert.group.MALFORMED, expert.severity.ERROR),
}
modbus.experts = { mx.bad_crc, mx.exception, mx.malformed, mx.truncated }

-- Adds `count` big-endian register values from `p`'s byte `off`, numbered from `first` when
-- the registers are known (nil in a read's response, which does not name them); returns them
-- as text ("2048,0").
local function modbus_values(tree, p, off, count, first)
  local values = {}
  for i = 0, count - 1 do
    local range = p(off + 2 * i, 2)
    local item = tree:add(m.value, range)
    if first then
      item:append_text(string.format(" (register %d, Modbus address %d)", first + i,
                                     40001 + first + i))
    end
    values[#values + 1] = tostring(range:uint())
  end
  return table.concat(values, ",")
end

-- Adds a starting register and quantity (`which`: "", "read_" or "write_") at `p`'s byte `off`,
-- with the control-table address the register starts at; returns both numbers.
local function modbus_span(tree, p, off, which)
  local start, quantity = p(off, 2):uint(), p(off + 2, 2):uint()
  tree:add(m[which .. "start"], p(off, 2))
  tree:add(m.table_address, p(off, 2), 2 * start):set_generated()
  tree:add(m[which .. "quantity"], p(off + 2, 2))
  return start, quantity
end

-- Decodes a frame's data `p` (nil when empty) for `fn` under `tree`; returns the Info text, or
-- nil when the data do not fit the function's layout.
local function modbus_data(tree, p, fn, is_response)
  local n = p and p:len() or 0
  local reads = fn == READ_HOLDING_REGISTERS or fn == READ_INPUT_REGISTERS
  if is_response and (reads or fn == READ_WRITE_MULTIPLE_REGISTERS) then
    if n < 1 or p(0, 1):uint() ~= n - 1 or (n - 1) % 2 ~= 0 then
      return nil
    end
    tree:add(m.byte_count, p(0, 1))
    return " values=" .. modbus_values(tree, p, 1, (n - 1) / 2, nil)
  end
  if reads then
    if n ~= 4 then
      return nil
    end
    local start, quantity = modbus_span(tree, p, 0, "")
    return string.format(" start=%d qty=%d", start, quantity)
  end
  if fn == WRITE_SINGLE_REGISTER then
    if n ~= 4 then
      return nil
    end
    local register = p(0, 2):uint()
    tree:add(m.register, p(0, 2))
    tree:add(m.table_address, p(0, 2), 2 * register):set_generated()
    return string.format(" reg=%d value=%s", register, modbus_values(tree, p, 2, 1, register))
  end
  if fn == WRITE_MULTIPLE_REGISTERS then
    if is_response then
      if n ~= 4 then
        return nil
      end
      local start, quantity = modbus_span(tree, p, 0, "")
      return string.format(" start=%d qty=%d", start, quantity)
    end
    if n < 5 or p(4, 1):uint() ~= n - 5 or (n - 5) % 2 ~= 0 then
      return nil
    end
    local start, quantity = modbus_span(tree, p, 0, "")
    tree:add(m.byte_count, p(4, 1))
    return string.format(" start=%d qty=%d values=%s", start, quantity,
                         modbus_values(tree, p, 5, (n - 5) / 2, start))
  end
  if fn == READ_WRITE_MULTIPLE_REGISTERS then
    if n < 9 or p(8, 1):uint() ~= n - 9 or (n - 9) % 2 ~= 0 then
      return nil
    end
    local read_start, read_quantity = modbus_span(tree, p, 0, "read_")
    local write_start, write_quantity = modbus_span(tree, p, 4, "write_")
    tree:add(m.byte_count, p(8, 1))
    return string.format(" read start=%d qty=%d write start=%d qty=%d values=%s", read_start,
                         read_quantity, write_start, write_quantity,
                         modbus_values(tree, p, 9, (n - 9) / 2, write_start))
  end
  if fn == DIAGNOSTICS then
    if n < 2 then
      return nil
    end
    tree:add(m.subfunction, p(0, 2))
    if n > 2 then
      tree:add(m.data, p(2, n - 2))
    end
    return string.format(" sub=0x%04x data=%d bytes", p(0, 2):uint(), n - 2)
  end
  if n > 0 then
    tree:add(m.data, p)
  end
  return n > 0 and string.format(" data=%d bytes", n) or ""
end

-- Dissects the record's line bytes `frame` as one Modbus RTU frame; returns its Info text.
local function dissect_modbus(frame, direction, tree)
  local total = frame:len()
  if total < MODBUS_MIN_FRAME then
    local item = tree:add(m.truncated, frame)
    item:add_proto_expert_info(mx.truncated)
    return "incomplete frame"
  end
  local is_response = direction == TO_CLIENT
  local ptree = tree:add(modbus, frame)
  ptree:add(m.type, frame, is_response and 1 or 0):set_generated()
  local address = frame(0, 1):uint()
  local aitem = ptree:add(m.address, frame(0, 1))
  if address == MODBUS_BROADCAST then
    aitem:append_text(" (broadcast)")
  end
  local code = frame(1, 1):uint()
  local fn = band(code, 0x7F)
  local fitem = ptree:add(m["function"], frame(1, 1))
  fitem:add(m.exception, frame(1, 1))
  local name = modbus_function_names[fn] or string.format("function 0x%02x", fn)
  local text = string.format("%s addr=%d %s", is_response and "Response" or "Request", address,
                             name)
  local p = total > MODBUS_MIN_FRAME and frame(2, total - MODBUS_MIN_FRAME) or nil
  if band(code, MODBUS_EXCEPTION_FLAG) ~= 0 then
    if p and p:len() == 1 then
      local exception = p:uint()
      local item = ptree:add(m.exception_code, p)
      local exception_name = modbus_exception_names[exception] or "unknown"
      item:add_proto_expert_info(mx.exception, string.format("Exception 0x%02x %s", exception,
                                                             exception_name))
      text = text .. string.format(" exception 0x%02x %s", exception, exception_name)
    else
      if p then
        ptree:add(m.data, p)
      end
      ptree:add_proto_expert_info(mx.malformed)
      text = text .. " malformed exception"
    end
  else
    local more = modbus_data(ptree, p, fn, is_response)
    if more == nil then
      ptree:add(m.data, p or frame(2, 0))
      ptree:add_proto_expert_info(mx.malformed)
      more = " malformed data"
    end
    text = text .. more
  end
  local range = frame(total - 2, 2)
  text = text .. verify(ptree:add_le(m.crc, range), ptree, m.crc_status, range, range:le_uint(),
                        crc16_modbus(frame:raw(0, total - 2)), mx.bad_crc, "CRC", "%04x")
  ptree:append_text(", " .. text)
  return text
end

function capture.dissector(buf, pinfo, tree)
  local len = buf:len()
  if len < PSEUDO_HEADER_BYTES then
    return 0
  end
  local version = buf(0, 1):uint()
  local direction = buf(1, 1):uint()
  local hint = buf(2, 1):uint()
  local port = buf(3, 1):uint()
  local htree = tree:add(capture, buf(0, PSEUDO_HEADER_BYTES))
  local vitem = htree:add(hf.version, buf(0, 1))
  htree:add(hf.direction, buf(1, 1))
  htree:add(hf.protocol, buf(2, 1))
  htree:add(hf.port, buf(3, 1))
  htree:append_text(string.format(", port %d, %s", port,
                                  direction == TO_SERVOS and "client to servos" or "servos to client"))
  pinfo.cols.protocol = "DXL"
  local servos = string.format("port %d", port)
  pinfo.cols.src = direction == TO_SERVOS and "client" or servos
  pinfo.cols.dst = direction == TO_SERVOS and servos or "client"
  if version ~= PSEUDO_HEADER_VERSION then
    vitem:add_proto_expert_info(ef.version)
    return len
  end
  if hint == MODBUS then
    pinfo.cols.protocol = "Modbus RTU"
    if len > PSEUDO_HEADER_BYTES then
      pinfo.cols.info = dissect_modbus(buf(PSEUDO_HEADER_BYTES), direction, tree)
    else
      pinfo.cols.info = dissect_modbus(buf(0, 0), direction, tree)
    end
    return len
  end

  local infos, protocols = {}, {}
  local pos, garbage_from = PSEUDO_HEADER_BYTES, nil
  local function flush_garbage(to)
    if garbage_from then
      local item = tree:add(f.garbage, buf(garbage_from, to - garbage_from))
      item:add_proto_expert_info(ef.garbage)
      infos[#infos + 1] = string.format("%d bytes of garbage", to - garbage_from)
      garbage_from = nil
    end
  end
  while pos < len do
    local kind, total = classify(buf, pos, len - pos, hint)
    if kind == "partial" and complete_packet_after(buf, pos, len, hint) then
      kind = nil
    end
    if kind == nil then
      garbage_from = garbage_from or pos
      pos = pos + 1
    else
      flush_garbage(pos)
      if kind == "partial" then
        local item = tree:add(f.truncated, buf(pos, total))
        item:add_proto_expert_info(ef.truncated)
        infos[#infos + 1] = "incomplete packet"
      else
        infos[#infos + 1] = dissect_packet(buf, pos, total, kind, direction, tree)
        protocols[kind] = true
      end
      pos = pos + total
    end
  end
  flush_garbage(len)
  if protocols.feetech then
    pinfo.cols.protocol = "FEETECH"
  elseif protocols.v1 and not protocols.v2 then
    pinfo.cols.protocol = "DXL 1.0"
  elseif protocols.v2 and not protocols.v1 then
    pinfo.cols.protocol = "DXL 2.0"
  end
  pinfo.cols.info = table.concat(infos, "; ")
  return len
end

-- LINKTYPE_USER0 (DLT 147) is Wireshark's WTAP_ENCAP_USER0.
DissectorTable.get("wtap_encap"):add((wtap_encaps or wtap).USER0, capture)
