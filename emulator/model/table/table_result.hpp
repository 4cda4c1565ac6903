#pragma once

#include <cstdint>
#include <string>

#include "wire/protocol_table.hpp"
#include "wire/status_error.hpp"

namespace dxlemu::model {

/// Why the control table refused a bus access. Protocol-neutral: the servo turns it into a 2.0
/// error number or 1.0 error bits.
enum class TableError {
  None,
  Access,      ///< undefined address, read-only item
  Locked,      ///< an EEPROM item while the EEPROM is locked (torque on, or 1.0 Lock)
  DataLength,  ///< 2.0 write covering only part of a multi-byte item
  DataRange,   ///< value outside the item's range or allowed values
  DataLimit,   ///< value beyond the item that limits it (e.g. Max Position Limit)
  AngleLimit,  ///< Goal Position outside CW/CCW Angle Limit in joint mode (AX, RX, EX, MX 1.0,
               ///< XL-320)
  ResultFail,  ///< the servo cannot do it now (Torque Enable after a hardware error shutdown)
};

/// The Protocol 2.0 error number for a refusal (protocol2.md "Error"); an Angle Limit refusal is
/// a Data Limit Error there.
wire::StatusError v2_status_error(TableError error);

/// The Protocol 1.0 error bits for a refusal (protocol1.md "Error"). 1.0 has no access, length or
/// limit errors: they are all the Range Error bit, except Angle Limit, which has its own bit.
std::uint8_t v1_error_bits(TableError error);

/// The protocol-neutral outcome of a refusal, which each protocol's status vocabulary turns into
/// its error byte (wire/protocol_table.hpp).
wire::Outcome outcome_of(TableError error);

/// The outcome of a bus access: None, or an error and a sentence saying which rule refused it
/// (for traces and the control API).
struct TableResult {
  TableError error = TableError::None;
  std::string detail;

  /// True when the access succeeded.
  bool ok() const { return error == TableError::None; }
  /// A refusal.
  static TableResult fail(TableError error, std::string detail) {
    return TableResult{error, std::move(detail)};
  }
};

}  // namespace dxlemu::model
