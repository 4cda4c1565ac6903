#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

// Who may use the web server: the token (in the query or the per-port cookie) and the Host and
// Origin checks of a WebSocket upgrade. Pure functions on header values, so that the rules are
// tested without sockets; io/web_server.cpp applies them.
namespace dxlemu::io::web {

/// A request target ("/path?query") split at its first '?'. No decoding.
struct Target {
  std::string_view path;
  std::string_view query;  ///< Empty when there is no '?'.
};

/// Splits `target`; nullopt unless it is in origin form (starts with '/'): absolute URLs,
/// "*" and the like are refused.
std::optional<Target> split_target(std::string_view target);

/// `text` with its %XX escapes decoded ('+' stays '+'); nullopt for a malformed escape.
std::optional<std::string> percent_decode(std::string_view text);

/// The decoded value of the first `name`=value pair of a query string ("a=1&token=x"); nullopt
/// when the name is absent or its value is malformed.
std::optional<std::string> query_value(std::string_view query, std::string_view name);

/// The values of every cookie called `name` in one Cookie header value ("a=1; b=2").
std::vector<std::string_view> cookie_values(std::string_view header, std::string_view name);

/// The cookie that carries the token for the server on `port`: browsers keep cookies per host,
/// not per port, so two daemons on one host need different names.
std::string token_cookie_name(std::uint16_t port);

/// The Set-Cookie value a request with the right token in its query gets.
std::string token_cookie(std::uint16_t port, std::string_view token);

/// Compares a secret in time that depends only on the lengths, not on where they differ.
bool same_secret(std::string_view given, std::string_view secret);

/// Formats an address for a URL or a Host header: IPv6 in brackets, IPv4-mapped IPv6 as IPv4.
/// `address` must be a numeric address (as Asio prints it).
std::string url_host(std::string_view address);

/// Whether a Host header value names one of `hosts` (url_host form, compared without regard to
/// case) with `port`; the port may be left out when it is 80, as browsers do.
bool host_allowed(std::string_view host, const std::vector<std::string>& hosts, std::uint16_t port);

/// Whether an Origin header value is the page of `host` (the request's Host header): exactly
/// "http://" + host, without regard to case. "null" and other sites' pages are refused.
bool origin_matches(std::string_view origin, std::string_view host);

}  // namespace dxlemu::io::web
