#include "io/web_access.hpp"

#include <algorithm>
#include <boost/asio/ip/address.hpp>
#include <cctype>
#include <charconv>

namespace dxlemu::io::web {
namespace access_detail {

int hex_digit(char c) {
  if (c >= '0' && c <= '9') {
    return c - '0';
  }
  if (c >= 'a' && c <= 'f') {
    return c - 'a' + 10;
  }
  if (c >= 'A' && c <= 'F') {
    return c - 'A' + 10;
  }
  return -1;
}

bool same_ignoring_case(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

std::string_view trim_spaces(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) {
    text.remove_prefix(1);
  }
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) {
    text.remove_suffix(1);
  }
  return text;
}

}  // namespace access_detail

using namespace access_detail;  // NOLINT: this file's helpers, named for the unity build

std::optional<Target> split_target(std::string_view target) {
  if (target.empty() || target.front() != '/') {
    return std::nullopt;
  }
  const std::size_t question = target.find('?');
  if (question == std::string_view::npos) {
    return Target{target, {}};
  }
  return Target{target.substr(0, question), target.substr(question + 1)};
}

std::optional<std::string> percent_decode(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '%') {
      out += text[i];
      continue;
    }
    if (text.size() - i < 3) {
      return std::nullopt;  // '%' needs two hex digits after it
    }
    const int high = hex_digit(text[i + 1]);
    const int low = hex_digit(text[i + 2]);
    if (high < 0 || low < 0) {
      return std::nullopt;
    }
    out += static_cast<char>(high * 16 + low);
    i += 2;
  }
  return out;
}

std::optional<std::string> query_value(std::string_view query, std::string_view name) {
  while (!query.empty()) {
    const std::size_t amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    query.remove_prefix(amp == std::string_view::npos ? query.size() : amp + 1);
    const std::size_t equals = pair.find('=');
    if (pair.substr(0, equals) == name) {
      return percent_decode(equals == std::string_view::npos ? std::string_view()
                                                             : pair.substr(equals + 1));
    }
  }
  return std::nullopt;
}

std::vector<std::string_view> cookie_values(std::string_view header, std::string_view name) {
  std::vector<std::string_view> values;
  while (!header.empty()) {
    const std::size_t semicolon = header.find(';');
    const std::string_view pair = trim_spaces(header.substr(0, semicolon));
    header.remove_prefix(semicolon == std::string_view::npos ? header.size() : semicolon + 1);
    const std::size_t equals = pair.find('=');
    if (equals != std::string_view::npos && trim_spaces(pair.substr(0, equals)) == name) {
      std::string_view value = trim_spaces(pair.substr(equals + 1));
      // RFC 6265 allows a value in double quotes.
      if (value.size() >= 2 && value.front() == '"' && value.back() == '"') {
        value = value.substr(1, value.size() - 2);
      }
      values.push_back(value);
    }
  }
  return values;
}

std::string token_cookie_name(std::uint16_t port) {
  return "dxlemu_token_" + std::to_string(port);
}

std::string token_cookie(std::uint16_t port, std::string_view token) {
  return token_cookie_name(port) + "=" + std::string(token) + "; Path=/; HttpOnly; SameSite=Strict";
}

bool same_secret(std::string_view given, std::string_view secret) {
  if (given.size() != secret.size()) {
    return false;
  }
  unsigned char difference = 0;
  for (std::size_t i = 0; i < secret.size(); ++i) {
    difference |= static_cast<unsigned char>(given[i] ^ secret[i]);
  }
  return difference == 0;
}

std::string url_host(std::string_view address) {
  boost::system::error_code ec;
  const auto parsed = boost::asio::ip::make_address(std::string(address), ec);
  if (ec) {
    return std::string(address);
  }
  if (parsed.is_v6() && parsed.to_v6().is_v4_mapped()) {
    return boost::asio::ip::make_address_v4(boost::asio::ip::v4_mapped, parsed.to_v6()).to_string();
  }
  return parsed.is_v6() ? "[" + parsed.to_string() + "]" : parsed.to_string();
}

bool host_allowed(std::string_view host, const std::vector<std::string>& hosts,
                  std::uint16_t port) {
  // "name:port", "[v6]:port", or either without the port.
  std::string_view name = host;
  std::string_view port_text;
  const std::size_t bracket = host.rfind(']');
  const std::size_t colon = host.rfind(':');
  if (colon != std::string_view::npos && (bracket == std::string_view::npos || colon > bracket)) {
    name = host.substr(0, colon);
    port_text = host.substr(colon + 1);
  }
  if (port_text.empty()) {
    if (port != 80 || name.size() != host.size()) {
      return false;  // no port (only the default one may go unsaid), or "name:" with none
    }
  } else {
    unsigned value = 0;
    const auto [end, ec] =
        std::from_chars(port_text.data(), port_text.data() + port_text.size(), value);
    if (ec != std::errc() || end != port_text.data() + port_text.size() || value != port) {
      return false;
    }
  }
  return std::any_of(hosts.begin(), hosts.end(),
                     [&](const std::string& allowed) { return same_ignoring_case(name, allowed); });
}

bool origin_matches(std::string_view origin, std::string_view host) {
  constexpr std::string_view kScheme = "http://";
  return !host.empty() && origin.size() == kScheme.size() + host.size() &&
         same_ignoring_case(origin.substr(0, kScheme.size()), kScheme) &&
         same_ignoring_case(origin.substr(kScheme.size()), host);
}

}  // namespace dxlemu::io::web
