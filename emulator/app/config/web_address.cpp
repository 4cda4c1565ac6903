#include "app/config/web_address.hpp"

#include <arpa/inet.h>

#include <array>
#include <charconv>
#include <stdexcept>

#include "app/config/model_library.hpp"

namespace dxlemu::app {
namespace web_address {

std::uint16_t port_of(std::string_view text, std::string_view whole) {
  unsigned value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || value > 65535) {
    throw std::invalid_argument("--web " + std::string(whole) +
                                ": the port must be a number from 0 to 65535, not \"" +
                                std::string(text) + "\"");
  }
  return static_cast<std::uint16_t>(value);
}

bool is_ipv4(const std::string& address) {
  std::array<unsigned char, 4> bytes{};
  return ::inet_pton(AF_INET, address.c_str(), bytes.data()) == 1;
}

bool is_ipv6(const std::string& address) {
  std::array<unsigned char, 16> bytes{};
  return ::inet_pton(AF_INET6, address.c_str(), bytes.data()) == 1;
}

}  // namespace web_address

bool WebAddress::loopback() const {
  return address == "::1" || (web_address::is_ipv4(address) && address.starts_with("127."));
}

WebAddress parse_web_address(std::string_view text) {
  WebAddress out;
  const std::size_t colon = text.rfind(':');
  if (colon == std::string_view::npos) {
    out.port = web_address::port_of(text, text);
    return out;
  }
  std::string host(text.substr(0, colon));
  out.port = web_address::port_of(text.substr(colon + 1), text);
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
    if (!web_address::is_ipv6(host)) {
      throw std::invalid_argument("--web " + std::string(text) + ": \"" + host +
                                  "\" is not an IPv6 address");
    }
  } else if (host == "localhost") {
    host = "127.0.0.1";
  } else if (!web_address::is_ipv4(host)) {
    throw std::invalid_argument("--web " + std::string(text) + ": \"" + host +
                                "\" is not a numeric address (e.g. 127.0.0.1, 0.0.0.0, [::1])");
  }
  out.address = host;
  return out;
}

std::filesystem::path shipped_web_dir() {
  return shipped_data_dir("DXLEMU_WEB_DIR", DXLEMU_BINDIR_TO_WEBDIR, "index.html",
                          DXLEMU_SOURCE_WEB_DIR);
}

}  // namespace dxlemu::app
