#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace dxlemu::app {

/// Where `dxlemu run --web [ADDR:]PORT` serves the web interface (docs/web.md).
struct WebAddress {
  /// A numeric IPv4 or IPv6 address (without brackets); "127.0.0.1" unless one was given.
  std::string address = "127.0.0.1";
  /// 0: any free port (the printed URL names the one taken).
  std::uint16_t port = 0;
  /// True when only this machine can connect (127.0.0.0/8, ::1).
  bool loopback() const;
};

/// Parses `--web`'s argument: `PORT`, `ADDR:PORT` or `[IPV6]:PORT`, where ADDR is a numeric
/// address or `localhost` (taken as 127.0.0.1). Throws std::invalid_argument saying what is wrong.
WebAddress parse_web_address(std::string_view text);

/// The web interface's files (index.html and what it loads), the first of: $DXLEMU_WEB_DIR when
/// set and not empty; the installed copy beside the executable (`../share/dxlemu/web`); else
/// the source tree's web/ this binary was built from.
std::filesystem::path shipped_web_dir();

}  // namespace dxlemu::app
