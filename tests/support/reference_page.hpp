#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace dxlemu::test {

/// One row of a control-table page in ../shared/reference/control-tables/, cells as printed
/// (links, <br /> and thousands separators removed).
struct ReferenceRow {
  unsigned address = 0;
  unsigned size = 0;
  std::string name;
  std::string access;   ///< "R" or "RW"
  std::string area;     ///< "EEPROM", "RAM" (the section heading) or "Hybrid" (an Area column)
  std::string initial;  ///< e.g. "1020", "-", "Max Torque"
  std::string range;    ///< e.g. "0 ~ 252"; XL-320's Min/Max columns are joined the same way
};

/// A parsed page: its rows with a concrete address, and whether it elides rows ("…", "...").
struct ReferencePage {
  std::vector<ReferenceRow> rows;
  bool has_elided_rows = false;
};

/// Parses the EEPROM and RAM tables of a model page (the tables whose header starts with
/// "Address" and has "Data Name" and "Access" columns, located by header text).
ReferencePage parse_reference_page(const std::filesystem::path& page);

/// A cell as a whole number ("1,020" -> 1020, "-250,961" -> -250961), or nullopt.
std::optional<long long> reference_number(const std::string& cell);

/// The reference folder beside the checkout (../shared/reference), or nullopt when absent.
std::optional<std::filesystem::path> reference_dir();

}  // namespace dxlemu::test
