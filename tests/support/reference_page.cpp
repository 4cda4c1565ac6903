#include "reference_page.hpp"
#include "text.hpp"

#include <algorithm>
#include <fstream>
#include <regex>
#include <stdexcept>

namespace dxlemu::test {
namespace {

// Markdown links become their text; <br>, &nbsp; and the like become spaces; runs of spaces fold.
// The patterns are compiled once: compiling them for every cell of every page took seconds (a
// minute and more under the sanitizers).
std::string clean(std::string cell) {
  static const std::regex link(R"(\[([^\]]*)\]\([^)]*\))");
  static const std::regex tag(R"(<[^>]*>)");
  static const std::regex entity(R"(&[a-z]+;)");
  static const std::regex spaces(R"(\s+)");
  cell = std::regex_replace(cell, link, "$1");
  cell = std::regex_replace(cell, tag, " ");
  cell = std::regex_replace(cell, entity, " ");
  cell = std::regex_replace(cell, spaces, " ");
  return trim(cell);
}

std::vector<std::string> split_row(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (std::size_t i = 1; i < line.size(); ++i) {  // skip the leading '|'
    if (line[i] == '|') {
      cells.push_back(clean(cell));
      cell.clear();
    } else {
      cell += line[i];
    }
  }
  return cells;
}

int column(const std::vector<std::string>& header, const std::string& prefix) {
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i].rfind(prefix, 0) == 0) {
      return static_cast<int>(i);
    }
  }
  return -1;
}

}  // namespace

std::optional<long long> reference_number(const std::string& cell) {
  // "1,044,479" groups thousands; "1, 2" (2XL430's two IDs) is a list, not a number.
  if (cell.find(", ") != std::string::npos) {
    return std::nullopt;
  }
  std::string digits;
  for (const char c : cell) {
    if (c != ',' && c != ' ') {
      digits += c;
    }
  }
  static const std::regex integer(R"(-?[0-9]+)");
  if (!std::regex_match(digits, integer)) {
    return std::nullopt;
  }
  return std::stoll(digits);
}

ReferencePage parse_reference_page(const std::filesystem::path& page) {
  std::ifstream in(page);
  if (!in) {
    throw std::runtime_error("cannot open " + page.string());
  }
  ReferencePage out;
  std::string line;
  std::string area;
  std::vector<std::string> header;
  while (std::getline(in, line)) {
    if (line.rfind('#', 0) == 0) {
      area = line.find("EEPROM") != std::string::npos ? "EEPROM"
             : line.find("RAM") != std::string::npos  ? "RAM"
                                                      : area;
      header.clear();
      continue;
    }
    if (line.rfind('|', 0) != 0) {
      header.clear();
      continue;
    }
    const auto cells = split_row(line);
    if (header.empty()) {
      const bool table_header = !cells.empty() && cells[0] == "Address" &&
                                column(cells, "Data Name") >= 0 && column(cells, "Access") >= 0;
      if (table_header) {
        header = cells;
      }
      continue;
    }
    if (!cells.empty() && cells[0].find("---") != std::string::npos) {
      continue;  // the |:---:| line
    }
    const auto address = reference_number(cells.at(0));
    const int size_col = column(header, "Size");
    const auto size = size_col >= 0 ? reference_number(cells.at(size_col)) : std::nullopt;
    if (!address || !size) {
      out.has_elided_rows = true;  // "…", "...": a series the page does not print in full
      continue;
    }
    ReferenceRow row;
    row.address = static_cast<unsigned>(*address);
    row.size = static_cast<unsigned>(*size);
    row.name = cells.at(column(header, "Data Name"));
    row.access = cells.at(column(header, "Access"));
    // One combined table (DYNAMIXEL-Y) says the area of each row: EEPROM, RAM or Hybrid.
    if (const int a = column(header, "Area"); a >= 0) {
      const std::string& cell = cells.at(a);
      row.area = cell == "EEPROM" || cell == "RAM" || cell == "Hybrid" ? cell : "";
    } else {
      row.area = area;
    }
    // Legacy PRO pages head the column "Default Value".
    const int initial =
        column(header, "Initial") >= 0 ? column(header, "Initial") : column(header, "Default");
    row.initial = cells.at(initial);
    if (const int r = column(header, "Range"); r >= 0) {
      row.range = cells.at(r);
    } else if (const int lo = column(header, "Min"), hi = column(header, "Max");
               lo >= 0 && hi >= 0) {
      row.range = cells.at(lo) + " ~ " + cells.at(hi);
    }
    out.rows.push_back(row);
  }
  return out;
}

std::optional<std::filesystem::path> reference_dir() {
  const std::filesystem::path dir(DXLEMU_REFERENCE_DIR);
  if (std::filesystem::is_directory(dir / "control-tables")) {
    return dir;
  }
  return std::nullopt;
}

}  // namespace dxlemu::test
