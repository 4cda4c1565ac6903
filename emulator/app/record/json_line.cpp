#include "app/record/json_line.hpp"

#include <array>
#include <charconv>
#include <nlohmann/json.hpp>

namespace dxlemu::app {
namespace {

constexpr std::string_view kHexDigits = "0123456789abcdef";

// The short escape nlohmann::json writes for `c`, or empty when it has none (the other control
// characters are written as \u00XX).
std::string_view short_escape(char c) {
  switch (c) {
    case '"':
      return "\\\"";
    case '\\':
      return "\\\\";
    case '\b':
      return "\\b";
    case '\f':
      return "\\f";
    case '\n':
      return "\\n";
    case '\r':
      return "\\r";
    case '\t':
      return "\\t";
    default:
      return {};
  }
}

}  // namespace

JsonLine::JsonLine() {
  out_.reserve(kTypicalSize);
  out_ += '{';
}

void JsonLine::key(std::string_view name) {
  if (out_.size() > 1) {
    out_ += ',';
  }
  quoted(name);
  out_ += ':';
}

void JsonLine::quoted(std::string_view value) {
  const std::size_t open = out_.size();
  out_ += '"';
  std::size_t plain = 0;  // the start of the characters not yet copied, which need no escape
  for (std::size_t i = 0; i < value.size(); ++i) {
    const auto c = static_cast<unsigned char>(value[i]);
    if (c >= 0x80) {
      // Rare (names from a config file): let nlohmann check the UTF-8 and replace what is
      // invalid.
      out_.resize(open);
      out_ += nlohmann::json(std::string(value))
                  .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
      return;
    }
    if (c >= 0x20 && c != '"' && c != '\\') {
      continue;
    }
    out_.append(value.substr(plain, i - plain));
    plain = i + 1;
    if (const std::string_view escape = short_escape(value[i]); !escape.empty()) {
      out_ += escape;
    } else {
      out_ += "\\u00";
      out_ += kHexDigits[c >> 4];
      out_ += kHexDigits[c & 0x0F];
    }
  }
  out_.append(value.substr(plain));
  out_ += '"';
}

JsonLine& JsonLine::text(std::string_view name, std::string_view value) {
  key(name);
  quoted(value);
  return *this;
}

JsonLine& JsonLine::integer(std::string_view name, std::int64_t value) {
  key(name);
  std::array<char, 24> digits{};
  const auto end = std::to_chars(digits.begin(), digits.end(), value).ptr;
  out_.append(digits.begin(), end);
  return *this;
}

JsonLine& JsonLine::real(std::string_view name, double value) {
  key(name);
  std::array<char, 32> digits{};
  const auto end = std::to_chars(digits.begin(), digits.end(), value).ptr;
  const std::string_view written(digits.data(), static_cast<std::size_t>(end - digits.begin()));
  out_ += written;
  if (written.find_first_of(".e") == std::string_view::npos) {
    out_ += ".0";  // as nlohmann::json writes an integral double
  }
  return *this;
}

std::string JsonLine::finish() {
  out_ += '}';
  return std::move(out_);
}

}  // namespace dxlemu::app
