// libFuzzer target for the web server's request checks (docs/web.md "Safety"): the pure functions
// of io/web_access.hpp (request target, %-escapes, query token, cookies, Host and Origin) and
// io/web_files.hpp (which file a path names, its Content-Type) on arbitrary request targets and
// header values. Each function is held to what its header promises, against a small reference
// model of that promise where one is short enough to be obviously right; resolve_file against a
// web root and a library root of its own (a temporary directory made at start, no symbolic
// links in it): whatever the path, a file it serves is one of the files put there to be served,
// inside its root both lexically and once canonical, and every such file is found under any
// %-encoding of its path.
//
// The input is lines ('\n'): the request target, the Host header, the Origin header, the Cookie
// header, the token, the address the server listens on, its port. Missing lines are empty; the
// token, the address and the port then take the daemon's usual kind of value.

#include <algorithm>
#include <array>
#include <boost/asio/ip/address.hpp>
#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "fuzz_require.hpp"
#include "io/web_access.hpp"
#include "io/web_files.hpp"

namespace dxlemu::fuzz {
// A named namespace: the target's sources are one unity batch with io/web_access.cpp and
// io/web_files.cpp, whose helpers are pulled into dxlemu::io::web.
namespace web_checks {

namespace fs = std::filesystem;
namespace web = io::web;

// ---- The roots resolve_file serves from ----

/// One file put into a root to be served: its area, its path under the root, the Content-Type
/// mime_type gives it.
struct Served {
  web::FileArea area;
  std::string_view relative;
  std::string_view type;
};

constexpr std::string_view kHtml = "text/html; charset=utf-8";
constexpr std::string_view kJs = "text/javascript; charset=utf-8";
constexpr std::array kServed = {
    Served{web::FileArea::WebRoot, "index.html", kHtml},
    Served{web::FileArea::WebRoot, "app.js", kJs},
    Served{web::FileArea::WebRoot, "css/site.css", "text/css; charset=utf-8"},
    Served{web::FileArea::WebRoot, "data/model.json", "application/json"},
    Served{web::FileArea::WebRoot, "Caps.PNG", "image/png"},
    Served{web::FileArea::WebRoot, "noext", "application/octet-stream"},
    Served{web::FileArea::WebRoot, "space name.txt", "text/plain; charset=utf-8"},
    Served{web::FileArea::Library, "three/three.module.js", kJs},
    Served{web::FileArea::Library, "three/addons/controls/OrbitControls.js", kJs},
    Served{web::FileArea::Library, "chart.js/chart.umd.js", kJs},
};

// Files that exist but must never be served: hidden names, a library directory other than the
// two, a file at the library root, a web root file shadowed by /lib/, and files beside the roots
// (one in a directory whose name starts with the web root's).
constexpr std::array<std::string_view, 8> kNotServed = {
    "web/.hidden",    "web/css/.site.css.swp",   "web/lib/three/decoy.js", "library/other/x.js",
    "library/top.js", "library/three/.cache.js", "web-private/secret.txt", "outside.txt",
};

/// A temporary directory holding web/ and library/, removed at exit.
class Roots {
 public:
  Roots() {
    std::string pattern = (fs::temp_directory_path() / "dxlemu-fuzz-web-XXXXXX").string();
    FUZZ_REQUIRE(mkdtemp(pattern.data()) != nullptr);
    base_ = pattern;
    web_ = base_ / "web";
    library_ = base_ / "library";
    for (const Served& served : kServed) {
      write(root(served.area) / served.relative);
    }
    for (const std::string_view relative : kNotServed) {
      write(base_ / relative);
    }
    fs::create_directories(web_ / "empty");
    canonical_web_ = fs::weakly_canonical(web_);
    canonical_library_ = fs::weakly_canonical(library_);
  }
  ~Roots() {
    std::error_code ignored;
    fs::remove_all(base_, ignored);
  }
  Roots(const Roots&) = delete;
  Roots& operator=(const Roots&) = delete;
  Roots(Roots&&) = delete;
  Roots& operator=(Roots&&) = delete;

  [[nodiscard]] const fs::path& web_root() const { return web_; }
  [[nodiscard]] const fs::path& library_root() const { return library_; }
  [[nodiscard]] const fs::path& root(web::FileArea area) const {
    return area == web::FileArea::Library ? library_ : web_;
  }
  [[nodiscard]] const fs::path& canonical_root(web::FileArea area) const {
    return area == web::FileArea::Library ? canonical_library_ : canonical_web_;
  }

 private:
  static void write(const fs::path& file) {
    fs::create_directories(file.parent_path());
    std::ofstream(file) << "x";
    FUZZ_REQUIRE(fs::is_regular_file(file));
  }

  fs::path base_;
  fs::path web_;
  fs::path library_;
  fs::path canonical_web_;
  fs::path canonical_library_;
};

const Roots& roots() {
  static const Roots made;
  return made;
}

// ---- Small references ----

FUZZ_NO_COVERAGE char ascii_lower(char c) {
  return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c;
}

FUZZ_NO_COVERAGE std::string lowered(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(), ascii_lower);
  return out;
}

FUZZ_NO_COVERAGE bool is_hex(char c) {
  return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
}

/// Bits the input chooses: which bytes an encoding escapes, in which case its hex digits are.
class Bits {
 public:
  explicit Bits(std::string_view input) : input_(input) {}
  FUZZ_NO_COVERAGE bool next() {
    if (input_.empty()) {
      return (at_++ % 3) == 0;
    }
    const std::size_t bit = at_++;
    const auto byte = static_cast<unsigned char>(input_[bit % input_.size()]);
    return ((byte >> ((bit / input_.size()) % 8)) & 1U) != 0;
  }

 private:
  std::string_view input_;
  std::size_t at_ = 0;
};

/// `text` with the bytes `bits` picks as %XX escapes (always '%', and '&', which would end a
/// query's value), the hex digits in the case it picks.
FUZZ_NO_COVERAGE std::string encode(std::string_view text, Bits& bits) {
  constexpr std::string_view kUpper = "0123456789ABCDEF";
  constexpr std::string_view kLower = "0123456789abcdef";
  std::string out;
  for (const char c : text) {
    if (c != '%' && c != '&' && !bits.next()) {
      out += c;
      continue;
    }
    const std::string_view digits = bits.next() ? kLower : kUpper;
    const auto byte = static_cast<unsigned char>(c);
    out += '%';
    out += digits[byte >> 4U];
    out += digits[byte & 0x0FU];
  }
  return out;
}

/// How many %XX escapes `text` holds; nullopt when a '%' lacks its two hex digits.
FUZZ_NO_COVERAGE std::optional<std::size_t> count_escapes(std::string_view text) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '%') {
      if (i + 2 >= text.size() || !is_hex(text[i + 1]) || !is_hex(text[i + 2])) {
        return std::nullopt;
      }
      ++count;
      i += 2;
    }
  }
  return count;
}

/// The raw value of the first pair called `name` in a query ("a=1&name=raw"): nullopt when there
/// is none, empty when the pair has no '='.
FUZZ_NO_COVERAGE std::optional<std::string_view> first_raw_value(std::string_view query,
                                                                 std::string_view name) {
  std::size_t start = 0;
  while (start < query.size()) {
    const std::size_t end = std::min(query.find('&', start), query.size());
    const std::string_view pair = query.substr(start, end - start);
    const std::size_t equals = pair.find('=');
    if (pair.substr(0, equals) == name) {
      return equals == std::string_view::npos ? std::string_view() : pair.substr(equals + 1);
    }
    start = end + 1;
  }
  return std::nullopt;
}

/// Whether a Host header names `allowed` with `port`: the name (any case), then ":" and decimal
/// digits of the port's value (leading zeros too), or nothing when the port is 80.
FUZZ_NO_COVERAGE bool names_host(std::string_view host, std::string_view allowed,
                                 std::uint16_t port) {
  if (host.size() < allowed.size() || lowered(host.substr(0, allowed.size())) != lowered(allowed)) {
    return false;
  }
  std::string_view rest = host.substr(allowed.size());
  if (rest.empty()) {
    return port == 80;
  }
  if (rest.front() != ':' || rest.size() < 2) {
    return false;
  }
  rest.remove_prefix(1);
  if (!std::all_of(rest.begin(), rest.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return false;
  }
  while (rest.size() > 1 && rest.front() == '0') {
    rest.remove_prefix(1);
  }
  return rest == std::to_string(port);
}

/// Whether `name` is "localhost" or a numeric address in url_host form: IPv4 dotted, IPv6 in
/// brackets.
FUZZ_NO_COVERAGE bool localhost_or_numeric(std::string_view name) {
  if (lowered(name) == "localhost") {
    return true;
  }
  const bool bracketed = name.size() >= 2 && name.front() == '[' && name.back() == ']';
  const std::string inner(bracketed ? name.substr(1, name.size() - 2) : name);
  boost::system::error_code ec;
  const auto address = boost::asio::ip::make_address(inner, ec);
  return !ec && address.is_v6() == bracketed;
}

/// Whether `file` is below `root`, by whole path components.
FUZZ_NO_COVERAGE bool is_below(const fs::path& file, const fs::path& root) {
  const auto [in_root, in_file] = std::mismatch(root.begin(), root.end(), file.begin(), file.end());
  return in_root == root.end() && in_file != file.end();
}

// ---- The checks, one function of the headers each ----

void check_split_target(std::string_view target) {
  const std::optional<web::Target> split = web::split_target(target);
  FUZZ_REQUIRE(split.has_value() == (!target.empty() && target.front() == '/'));
  if (!split) {
    return;
  }
  FUZZ_REQUIRE(split->path.data() == target.data());
  FUZZ_REQUIRE(split->path.find('?') == std::string_view::npos);
  if (split->path.size() == target.size()) {
    FUZZ_REQUIRE(split->query.empty());
  } else {
    FUZZ_REQUIRE(target[split->path.size()] == '?');
    FUZZ_REQUIRE(split->query == target.substr(split->path.size() + 1));
  }
}

void check_percent_decode(std::string_view text, Bits& bits) {
  const std::optional<std::string> decoded = web::percent_decode(text);
  const std::optional<std::size_t> escapes = count_escapes(text);
  FUZZ_REQUIRE_MSG(decoded.has_value() == escapes.has_value(), "\"%.*s\"",
                   static_cast<int>(text.size()), text.data());
  if (decoded) {
    FUZZ_REQUIRE(decoded->size() == text.size() - 2 * *escapes);
    if (*escapes == 0) {
      FUZZ_REQUIRE(*decoded == text);
    }
  }
  // Any bytes, '+' and '%' included, come back from any encoding of them.
  const std::string encoded = encode(text, bits);
  const std::optional<std::string> round_trip = web::percent_decode(encoded);
  FUZZ_REQUIRE_MSG(round_trip && *round_trip == text, "\"%s\"", encoded.c_str());
}

void check_query(std::string_view query, const std::string& token, Bits& bits) {
  for (const std::string_view name : {std::string_view("token"), std::string_view("a")}) {
    const std::optional<std::string> value = web::query_value(query, name);
    const std::optional<std::string_view> raw = first_raw_value(query, name);
    if (!raw) {
      FUZZ_REQUIRE(!value);
      continue;
    }
    // The value ends at the pair's '&': one can only come from the value's own %26.
    FUZZ_REQUIRE(raw->find('&') == std::string_view::npos);
    FUZZ_REQUIRE(value == web::percent_decode(*raw));
    if (value && value->find('&') != std::string::npos) {
      FUZZ_REQUIRE(lowered(*raw).find("%26") != std::string::npos);
    }
    if (value) {
      FUZZ_REQUIRE(web::same_secret(*value, token) == (*value == token));
    }
  }
  // The token appended as a pair of its own is found, whatever came before, unless a pair
  // called token came first.
  if (!first_raw_value(query, "token")) {
    const std::string with_token = std::string(query) + "&token=" + encode(token, bits);
    FUZZ_REQUIRE(web::query_value(with_token, "token") == token);
  }
}

void check_cookies(std::string_view header, std::uint16_t port, const std::string& token) {
  const std::string name = web::token_cookie_name(port);
  const std::vector<std::string_view> values = web::cookie_values(header, name);
  for (const std::string_view value : values) {
    FUZZ_REQUIRE(value.data() >= header.data() &&
                 value.data() + value.size() <= header.data() + header.size());
    FUZZ_REQUIRE(value.find(';') == std::string_view::npos);
    (void)web::same_secret(value, token);
  }
  FUZZ_REQUIRE(values.size() <=
               static_cast<std::size_t>(std::count(header.begin(), header.end(), '=')));
  if (token.find(';') != std::string::npos) {
    return;
  }
  // A cookie of ours appended to the header is found last, the header's own as before; in
  // double quotes it is found whatever its spaces.
  const std::string quoted = std::string(header) + "; " + name + "=\"" + token + "\"";
  std::vector<std::string_view> expected = values;
  expected.push_back(token);
  const std::vector<std::string_view> found = web::cookie_values(quoted, name);
  FUZZ_REQUIRE(std::equal(found.begin(), found.end(), expected.begin(), expected.end()));
  const auto spacious = [](char c) { return c == ' ' || c == '\t'; };
  const bool plain = !token.empty() && !spacious(token.front()) && !spacious(token.back()) &&
                     !(token.size() >= 2 && token.front() == '"' && token.back() == '"');
  if (plain) {
    const std::string appended = std::string(header) + ";" + name + "=" + token;
    const std::vector<std::string_view> again = web::cookie_values(appended, name);
    FUZZ_REQUIRE(std::equal(again.begin(), again.end(), expected.begin(), expected.end()));
    // What Set-Cookie gives the browser is what it sends back.
    const std::string set_cookie = web::token_cookie(port, token);
    FUZZ_REQUIRE(set_cookie.starts_with(name + "=" + token + ";"));
    const std::string sent_back = set_cookie.substr(0, set_cookie.find(';', name.size()));
    const std::vector<std::string_view> back = web::cookie_values(sent_back, name);
    FUZZ_REQUIRE(back.size() == 1 && back.front() == token);
  }
}

/// url_host of a parsed address: IPv4 (an IPv4-mapped IPv6 too) as itself, IPv6 in brackets,
/// and either parses back to the same address.
void check_url_host(const boost::asio::ip::address& address) {
  const std::string host = web::url_host(address.to_string());
  const bool mapped = address.is_v6() && address.to_v6().is_v4_mapped();
  const bool bracketed = host.size() >= 2 && host.front() == '[' && host.back() == ']';
  FUZZ_REQUIRE_MSG(bracketed == (address.is_v6() && !mapped), "%s", host.c_str());
  boost::system::error_code ec;
  const auto back =
      boost::asio::ip::make_address(bracketed ? host.substr(1, host.size() - 2) : host, ec);
  FUZZ_REQUIRE_MSG(!ec, "%s", host.c_str());
  if (mapped) {
    FUZZ_REQUIRE(back.is_v4() && back == boost::asio::ip::make_address_v4(
                                             boost::asio::ip::v4_mapped, address.to_v6()));
  } else {
    FUZZ_REQUIRE(back == address);
  }
  FUZZ_REQUIRE(localhost_or_numeric(host));
}

void check_host_and_origin(std::string_view host, std::string_view origin,
                           const std::vector<std::string>& hosts, std::uint16_t port) {
  const bool allowed = web::host_allowed(host, hosts, port);
  const bool expected = std::any_of(hosts.begin(), hosts.end(), [&](const std::string& name) {
    return names_host(host, name, port);
  });
  FUZZ_REQUIRE_MSG(allowed == expected, "Host \"%.*s\", port %u: %d", static_cast<int>(host.size()),
                   host.data(), static_cast<unsigned>(port), static_cast<int>(allowed));
  if (allowed) {
    // The DNS-rebinding rule: no name but localhost gets through, only numeric addresses.
    for (const std::string& name : hosts) {
      if (names_host(host, name, port)) {
        FUZZ_REQUIRE_MSG(localhost_or_numeric(name), "Host \"%.*s\" as %s",
                         static_cast<int>(host.size()), host.data(), name.c_str());
      }
    }
  }
  for (const std::string& name : hosts) {
    FUZZ_REQUIRE(web::host_allowed(name + ":" + std::to_string(port), hosts, port));
  }

  const bool matches = web::origin_matches(origin, host);
  FUZZ_REQUIRE(matches == (!host.empty() && lowered(origin) == "http://" + lowered(host)));
  if (!host.empty()) {
    FUZZ_REQUIRE(web::origin_matches("http://" + std::string(host), host));
    FUZZ_REQUIRE(!web::origin_matches("https://" + std::string(host), host));
  }
  FUZZ_REQUIRE(!web::origin_matches("null", host));
}

void check_mime_type(const fs::path& file) {
  const std::string_view type = web::mime_type(file);
  FUZZ_REQUIRE(!type.empty());
  FUZZ_REQUIRE(web::mime_type(lowered(file.string())) == type);
}

void check_resolve(std::string_view path) {
  const Roots& dirs = roots();
  web::FileLookup lookup;
  try {
    lookup = web::resolve_file(path, dirs.web_root(), dirs.library_root());
  } catch (const std::exception& e) {
    FUZZ_REQUIRE_MSG(false, "resolve_file threw: %s", e.what());
  }
  FUZZ_REQUIRE(lookup.status == 200 || lookup.status == 400 || lookup.status == 404);
  FUZZ_REQUIRE((lookup.status == 200) == lookup.reason.empty());
  FUZZ_REQUIRE((lookup.status == 200) == !lookup.file.empty());

  const std::optional<std::string> decoded = web::percent_decode(path);
  const bool bad = !decoded || decoded->find('\0') != std::string::npos ||
                   decoded->find('\\') != std::string::npos || decoded->empty() ||
                   decoded->front() != '/';
  FUZZ_REQUIRE((lookup.status == 400) == bad);
  if (lookup.status != 200) {
    return;
  }
  // The file is the path's own under its root, and one of those put there to be served.
  const std::string_view rest = std::string_view(*decoded).substr(1);
  const bool library = lookup.area == web::FileArea::Library;
  FUZZ_REQUIRE(library == (rest.starts_with("lib/three/") || rest.starts_with("lib/chart.js/")));
  const std::string_view relative =
      library ? rest.substr(4) : (rest.empty() ? std::string_view("index.html") : rest);
  FUZZ_REQUIRE(lookup.file == dirs.root(lookup.area) / relative);
  const auto served = std::find_if(kServed.begin(), kServed.end(), [&](const Served& s) {
    return s.area == lookup.area && s.relative == relative;
  });
  FUZZ_REQUIRE_MSG(served != kServed.end(), "served %s", lookup.file.c_str());
  FUZZ_REQUIRE(web::mime_type(lookup.file) == served->type);
  // The temporary roots hold no symbolic links: canonical, the file is still below its root.
  FUZZ_REQUIRE(fs::is_regular_file(lookup.file));
  FUZZ_REQUIRE_MSG(is_below(fs::weakly_canonical(lookup.file), dirs.canonical_root(lookup.area)),
                   "%s", lookup.file.c_str());
}

/// Every file put there to be served is found under the %-encoding `bits` picks of its path.
void check_served_files(Bits& bits) {
  const Roots& dirs = roots();
  for (const Served& served : kServed) {
    const std::string path = std::string(served.area == web::FileArea::Library ? "/lib/" : "/") +
                             std::string(served.relative);
    const web::FileLookup lookup =
        web::resolve_file(encode(path, bits), dirs.web_root(), dirs.library_root());
    FUZZ_REQUIRE_MSG(lookup.status == 200 && lookup.area == served.area &&
                         lookup.file == dirs.root(served.area) / served.relative,
                     "%s: %u %s", path.c_str(), lookup.status, lookup.reason.c_str());
  }
  FUZZ_REQUIRE(web::resolve_file("/", dirs.web_root(), dirs.library_root()).file ==
               dirs.web_root() / "index.html");
}

/// The address the server listens on: line 5 as the daemon parses --web's (brackets and
/// "localhost" allowed), 127.0.0.1 when it is none.
boost::asio::ip::address listen_address(std::string_view text) {
  std::string inner(text);
  if (inner.size() >= 2 && inner.front() == '[' && inner.back() == ']') {
    inner = inner.substr(1, inner.size() - 2);
  }
  if (inner == "localhost") {
    inner = "127.0.0.1";
  }
  boost::system::error_code ec;
  const auto parsed = boost::asio::ip::make_address(inner, ec);
  return ec ? boost::asio::ip::make_address_v4("127.0.0.1") : parsed;
}

std::uint16_t listen_port(std::string_view text) {
  std::uint16_t port = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), port);
  return ec == std::errc() && end == text.data() + text.size() ? port : 8080;
}

}  // namespace web_checks
}  // namespace dxlemu::fuzz

/// libFuzzer's entry point: the input's lines are a request target, Host, Origin, Cookie, the
/// token, the server's address and port.
// NOLINTNEXTLINE(readability-identifier-naming): the name libFuzzer calls
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace dxlemu::fuzz::web_checks;
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast): libFuzzer gives bytes
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  constexpr std::size_t kFields = 7;
  std::array<std::string_view, kFields> field{};
  std::size_t start = 0;
  for (std::size_t i = 0; i < kFields && start <= input.size(); ++i) {
    const std::size_t end = std::min(input.find('\n', start), input.size());
    field[i] = input.substr(start, end - start);
    start = end + 1;
  }
  const auto [target, host, origin, cookie, token_line, address_line, port_line] = field;
  const std::string token =
      token_line.empty() ? "0123456789abcdef0123456789abcdef" : std::string(token_line);
  const boost::asio::ip::address address = listen_address(address_line);
  const std::uint16_t port = listen_port(port_line);
  Bits bits(input);

  check_split_target(target);
  check_percent_decode(target, bits);
  check_percent_decode(cookie, bits);
  check_resolve(target);
  if (const auto split = dxlemu::io::web::split_target(target)) {
    if (split->path.size() != target.size()) {
      check_resolve(split->path);
    }
    check_query(split->query, token, bits);
  } else {
    check_query(target, token, bits);
  }
  check_mime_type(std::filesystem::path(target));
  check_served_files(bits);

  check_cookies(cookie, port, token);
  FUZZ_REQUIRE(dxlemu::io::web::same_secret(token, token));
  FUZZ_REQUIRE(dxlemu::io::web::same_secret(cookie, token) == (cookie == token));

  check_url_host(address);
  // As the server allows: the fixed names, the address it listens on, and the one the
  // connection came to (here the same).
  const std::vector<std::string> hosts = {"localhost", "127.0.0.1", "[::1]",
                                          dxlemu::io::web::url_host(address.to_string())};
  check_host_and_origin(host, origin, hosts, port);
  return 0;
}
