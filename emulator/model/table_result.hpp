#pragma once

#include <string>

namespace dxlemu::model {

/// Why the control table refused a bus access. Protocol-neutral: the servo turns it into a 2.0
/// error number or 1.0 error bits.
enum class TableError {
  None,
  Access,      ///< undefined address, read-only item, EEPROM locked (torque on, or 1.0 Lock)
  DataLength,  ///< 2.0 write covering only part of a multi-byte item
  DataRange,   ///< value outside the item's range or allowed values
  DataLimit,   ///< value beyond the item that limits it (e.g. Max Position Limit)
};

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
