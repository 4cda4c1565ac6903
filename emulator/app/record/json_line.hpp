#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace dxlemu::app {

/// One JSON object on one line, built by appending to a string. The trace writes two lines per
/// round trip on the bus; building them as nlohmann::ordered_json and dumping them cost about
/// three times what the round trip itself costs (docs/benchmarks.md "Hot spots removed, before and
/// after").
///
/// Members come out in the order they are added. Text is escaped as nlohmann::json escapes it
/// (invalid UTF-8 becomes U+FFFD), numbers are written as nlohmann::json writes them.
class JsonLine {
 public:
  /// An empty object.
  JsonLine();

  /// Adds `key` with a string value.
  JsonLine& text(std::string_view key, std::string_view value);
  /// Adds `key` with an integer value.
  JsonLine& integer(std::string_view key, std::int64_t value);
  /// Adds `key` with a floating-point value (shortest form that reads back the same; an
  /// integral value keeps a ".0", e.g. 2.0).
  JsonLine& real(std::string_view key, double value);

  /// The object, closed: "{...}". Leaves this JsonLine empty (to be discarded).
  std::string finish();

 private:
  void key(std::string_view name);
  void quoted(std::string_view value);

  static constexpr std::size_t kTypicalSize = 256;  // a trace line with its hex and text
  std::string out_;
};

}  // namespace dxlemu::app
