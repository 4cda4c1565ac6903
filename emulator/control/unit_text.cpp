#include "control/unit_text.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>

namespace dxlemu::control {
namespace {

constexpr std::size_t kThousandsGroup = 3;
constexpr int kSignificantDigits = 12;
constexpr double kTen = 10;

bool is_digit(char c) {
  return std::isdigit(static_cast<unsigned char>(c)) != 0;
}

void skip_spaces(std::string_view& text) {
  while (!text.empty() && text.front() == ' ') {
    text.remove_prefix(1);
  }
}

/// The figure at the start of `text` ("58,000", "0.229"), consumed; nullopt when there is none.
/// Commas must group thousands; the digits without them are read as one number.
std::optional<double> leading_figure(std::string_view& text) {
  std::string digits;
  std::size_t i = 0;
  std::size_t group = 0;  // digits since the last comma
  bool grouped = false;
  while (i < text.size() && (is_digit(text[i]) || text[i] == ',')) {
    if (text[i] == ',') {
      if (digits.empty() || (grouped && group != kThousandsGroup)) {
        return std::nullopt;
      }
      grouped = true;
      group = 0;
    } else {
      digits += text[i];
      ++group;
    }
    ++i;
  }
  if (digits.empty() || (grouped && group != kThousandsGroup)) {
    return std::nullopt;
  }
  if (i < text.size() && text[i] == '.') {
    digits += '.';
    ++i;
    const std::size_t fraction = i;
    while (i < text.size() && is_digit(text[i])) {
      digits += text[i];
      ++i;
    }
    if (i == fraction) {
      return std::nullopt;
    }
  }
  double figure = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), figure);
  if (error != std::errc{} || end != digits.data() + digits.size()) {
    return std::nullopt;
  }
  text.remove_prefix(i);
  return figure;
}

}  // namespace

std::optional<ScaledUnit> scaled_unit(std::string_view text) {
  skip_spaces(text);
  const auto figure = leading_figure(text);
  if (!figure || *figure <= 0) {
    return std::nullopt;
  }
  skip_spaces(text);
  std::string_view unit;
  if (!text.empty() && text.front() == '[') {
    // DYNAMIXEL's "0.229 [rev/min]".
    text.remove_prefix(1);
    const std::size_t close = text.find(']');
    if (close == std::string_view::npos) {
      return std::nullopt;
    }
    unit = text.substr(0, close);
    text.remove_prefix(close + 1);
    skip_spaces(text);
    if (!text.empty()) {
      return std::nullopt;  // more after the unit: "214.577 [rev/min²] / 1 [ms]"
    }
  } else {
    // FEETECH's "0.1V", "8.7°/s²": the unit is the rest, one word without figures, so that a
    // ratio ("0.732RPM/0.0146RPM", "1ms/0.1%") or a fraction ("1/R") is not taken for one.
    while (!text.empty() && text.back() == ' ') {
      text.remove_suffix(1);
    }
    unit = text;
    if (unit.starts_with('/') ||
        std::any_of(unit.begin(), unit.end(), [](char c) { return is_digit(c) || c == ' '; })) {
      return std::nullopt;
    }
  }
  if (unit.empty() || unit.find_first_of("[]") != std::string_view::npos) {
    return std::nullopt;
  }
  return ScaledUnit{*figure, std::string(unit)};
}

double scaled_value(std::int64_t value, double factor) {
  const double product = static_cast<double>(value) * factor;
  if (product == 0 || !std::isfinite(product)) {
    return product;
  }
  // Rounding by a power of ten that is exact as a double (10^0 ~ 10^22) leaves the nearest
  // double to the rounded decimal, which JSON then writes in its shortest form.
  const int exponent = static_cast<int>(std::floor(std::log10(std::fabs(product))));
  const int shift = kSignificantDigits - 1 - exponent;
  if (shift >= 0) {
    const double scale = std::pow(kTen, shift);
    return std::round(product * scale) / scale;
  }
  const double scale = std::pow(kTen, -shift);
  return std::round(product / scale) * scale;
}

}  // namespace dxlemu::control
