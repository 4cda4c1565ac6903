// WebServer over real loopback sockets, its io_context run by hand; the clients (plain HTTP over
// a socket, Beast's WebSocket client) run on the same io_context, so every wait is run_until
// something happened, never a sleep.
#include "io/web_server.hpp"

#include <catch2/catch.hpp>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core/buffers_to_string.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/http/parser.hpp>
#include <boost/beast/http/read.hpp>
#include <boost/beast/http/string_body.hpp>
#include <boost/beast/websocket/stream.hpp>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "io/web_access.hpp"
#include "io/web_files.hpp"
#include "io_rig.hpp"

// A named namespace around the helpers and the cases: in a unity build this file shares a
// compiler run with control_server_test.cpp, whose helpers have the same names.
namespace dxlemu::web_server_test {

namespace beast = boost::beast;
namespace http = boost::beast::http;
namespace websocket = boost::beast::websocket;
using tcp = boost::asio::ip::tcp;
using dxlemu::io::WebServer;
using dxlemu::io::WebServerOptions;
using dxlemu::io::WebSession;
using dxlemu::test::IoTempDir;
using dxlemu::test::run_until;
using dxlemu::test::settle;
namespace fs = std::filesystem;
namespace web = dxlemu::io::web;

constexpr std::string_view kToken = "0123456789abcdef0123456789abcdef";

// Upper-cases the line; "throw" throws, "quiet" answers nothing, "id" answers the session's id.
std::string upper_case(std::string_view line, WebSession& session) {
  if (line == "throw") {
    throw std::runtime_error("boom");
  }
  if (line == "quiet") {
    return {};
  }
  if (line == "id") {
    return std::to_string(session.id());
  }
  std::string out(line);
  for (char& c : out) {
    c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  return out;
}

void write_file(const fs::path& path, std::string_view text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

using Lines = std::vector<std::string>;

Lines split_lines(std::string_view text) {
  Lines lines;
  while (!text.empty()) {
    const std::size_t newline = text.find('\n');
    lines.emplace_back(text.substr(0, newline));
    text.remove_prefix(newline == std::string_view::npos ? text.size() : newline + 1);
  }
  return lines;
}

// A server on a free loopback port, serving a small web root and library tree of a temporary
// directory, with the sessions it reported closed.
struct Rig {
  explicit Rig(const std::function<void(WebServerOptions&)>& tweak = {},
               WebServer::Handler handler = upper_case) {
    write_file(dir.path() / "web/index.html", "<p>index</p>");
    write_file(dir.path() / "web/app.js", "let app;");
    write_file(dir.path() / "web/app.js.map", "{}");
    write_file(dir.path() / "web/style.css", "p {}");
    write_file(dir.path() / "web/logo.png", "PNG");
    write_file(dir.path() / "web/icon.svg", "<svg/>");
    write_file(dir.path() / "web/data.json", "[]");
    write_file(dir.path() / "web/.hidden", "hidden");
    write_file(dir.path() / "lib/three/three.module.js", "export {}");
    write_file(dir.path() / "lib/chart.js/chart.js", "chart");
    write_file(dir.path() / "lib/jquery/jquery.js", "jquery");
    write_file(dir.path() / "secret.txt", "secret");
    WebServerOptions options;
    options.token = std::string(kToken);
    options.web_root = dir.path() / "web";
    options.library_root = dir.path() / "lib";
    options.event_interval = std::chrono::milliseconds(5);
    if (tweak) {
      tweak(options);
    }
    server = std::make_unique<WebServer>(
        io, options, std::move(handler),
        WebServer::Replies{[](std::string_view what) { return "internal: " + std::string(what); }});
    server->on_close([this](WebSession& session) { closed.push_back(session.id()); });
  }
  tcp::endpoint endpoint() const {
    return {boost::asio::ip::make_address("127.0.0.1"), server->port()};
  }
  std::string host() const { return "127.0.0.1:" + std::to_string(server->port()); }
  std::string cookie() const {
    return "dxlemu_token_" + std::to_string(server->port()) + "=" + std::string(kToken);
  }

  IoTempDir dir;
  boost::asio::io_context io;
  // Before the server: its destructor reports the sessions still open.
  std::vector<std::uint64_t> closed;
  std::unique_ptr<WebServer> server;
};

// A plain TCP client speaking HTTP by hand.
class HttpClient {
 public:
  explicit HttpClient(Rig& rig) : rig_(rig), socket_(rig.io) { socket_.connect(rig.endpoint()); }

  // Writes `raw` (the kernel takes it whole: no need for the server to run meanwhile).
  void write(std::string_view raw) { boost::asio::write(socket_, boost::asio::buffer(raw)); }
  // A request for `target` with the Host header and `headers` ("Name: value\r\n" each).
  void request(std::string_view target, std::string_view headers = {},
               std::string_view method = "GET") {
    write(std::string(method) + " " + std::string(target) + " HTTP/1.1\r\nHost: " + rig_.host() +
          "\r\n" + std::string(headers) + "\r\n");
  }
  // Reads one response (of a HEAD request: without a body).
  http::response<http::string_body> response(bool head = false) {
    http::response_parser<http::string_body> parser;
    parser.skip(head);
    bool done = false;
    beast::error_code error;
    http::async_read(socket_, buffer_, parser, [&](const beast::error_code& ec, std::size_t) {
      error = ec;
      done = true;
    });
    REQUIRE(run_until(rig_.io, [&] { return done; }));
    INFO(error.message());
    REQUIRE_FALSE(error);
    return parser.release();
  }
  http::response<http::string_body> get(std::string_view target, std::string_view headers = {}) {
    request(target, headers);
    return response();
  }
  // Whether the server has closed the connection (waits for it).
  bool closed_by_server() {
    bool done = false;
    beast::error_code error;
    buffer_.consume(buffer_.size());
    socket_.async_read_some(buffer_.prepare(4096), [&](const beast::error_code& ec, std::size_t) {
      error = ec;
      done = true;
    });
    REQUIRE(run_until(rig_.io, [&] { return done; }));
    return error == boost::asio::error::eof || error == boost::asio::error::connection_reset;
  }

 private:
  Rig& rig_;
  tcp::socket socket_;
  beast::flat_buffer buffer_;
};

// The status of a GET of `target` on a connection of its own.
unsigned status_of(Rig& rig, std::string_view target, std::string_view headers = {}) {
  HttpClient client(rig);
  return client.get(target, headers).result_int();
}

std::string query_token() {
  return "token=" + std::string(kToken);
}

// Beast's WebSocket client, every operation waited for with run_until.
class WsClient {
 public:
  // `receive_buffer`: the socket's receive buffer in bytes, 0 for the kernel's default.
  explicit WsClient(Rig& rig, int receive_buffer = 0) : rig_(rig), ws_(rig.io) {
    tcp::socket& socket = ws_.next_layer();
    socket.open(tcp::v4());
    if (receive_buffer > 0) {
      socket.set_option(tcp::socket::receive_buffer_size(receive_buffer));
    }
    socket.connect(rig.endpoint());
  }

  // Upgrades with `target`, Host `host` (the server's address when empty) and Origin `origin`
  // (none when empty; "http://" + host when "same"); returns the HTTP status of the answer.
  unsigned handshake(const std::string& target = "/ws?" + query_token(),
                     std::string origin = "same", std::string host = {},
                     const std::string& cookie = {}) {
    if (host.empty()) {
      host = rig_.host();
    }
    if (origin == "same") {
      origin = "http://" + host;
    }
    ws_.set_option(websocket::stream_base::decorator([origin, cookie](websocket::request_type& r) {
      if (!origin.empty()) {
        r.set(http::field::origin, origin);
      }
      if (!cookie.empty()) {
        r.set(http::field::cookie, cookie);
      }
    }));
    websocket::response_type response;
    bool done = false;
    ws_.async_handshake(response, host, target, [&](const beast::error_code&) { done = true; });
    REQUIRE(run_until(rig_.io, [&] { return done; }));
    return response.result_int();
  }
  void send(const std::string& text, bool binary = false) {
    ws_.binary(binary);
    bool done = false;
    beast::error_code error;
    ws_.async_write(boost::asio::buffer(text), [&](const beast::error_code& ec, std::size_t) {
      error = ec;
      done = true;
    });
    REQUIRE(run_until(rig_.io, [&] { return done; }));
    REQUIRE_FALSE(error);
  }
  // The next message; empty with error() set when the connection ended instead.
  std::string receive() {
    beast::flat_buffer buffer;
    bool done = false;
    ws_.async_read(buffer, [&](const beast::error_code& ec, std::size_t) {
      error_ = ec;
      done = true;
    });
    REQUIRE(run_until(rig_.io, [&] { return done; }));
    return error_ ? std::string() : beast::buffers_to_string(buffer.data());
  }
  // Messages until `count` lines came, as lines.
  Lines receive_lines(std::size_t count) {
    Lines lines;
    while (lines.size() < count) {
      const std::string message = receive();
      REQUIRE_FALSE(error_);
      for (std::string& line : split_lines(message)) {
        lines.push_back(std::move(line));
      }
    }
    return lines;
  }
  const beast::error_code& error() const { return error_; }
  std::uint16_t close_code() const { return ws_.reason().code; }
  tcp::socket& socket() { return ws_.next_layer(); }

 private:
  Rig& rig_;
  websocket::stream<tcp::socket> ws_;
  beast::error_code error_;
};

TEST_CASE("Access rules: query token, cookie, Host and Origin", "[io][web_server]") {
  CHECK(web::query_value("a=1&token=ab%63&token=x", "token") == "abc");
  CHECK(web::query_value("tokens=1", "token") == std::nullopt);
  CHECK(web::query_value("token=%zz", "token") == std::nullopt);
  CHECK(web::cookie_values("a=1; dxlemu_token_80=\"t\";dxlemu_token_80=u", "dxlemu_token_80") ==
        std::vector<std::string_view>{"t", "u"});
  CHECK(web::token_cookie(8080, "t") == "dxlemu_token_8080=t; Path=/; HttpOnly; SameSite=Strict");
  CHECK(web::same_secret("abc", "abc"));
  CHECK_FALSE(web::same_secret("abd", "abc"));
  CHECK_FALSE(web::same_secret("ab", "abc"));
  CHECK(web::url_host("::1") == "[::1]");
  CHECK(web::url_host("::ffff:10.0.0.1") == "10.0.0.1");
  CHECK(web::url_host("10.0.0.1") == "10.0.0.1");

  const std::vector<std::string> hosts{"localhost", "127.0.0.1", "[::1]"};
  CHECK(web::host_allowed("localhost:8080", hosts, 8080));
  CHECK(web::host_allowed("LocalHost:8080", hosts, 8080));
  CHECK(web::host_allowed("[::1]:8080", hosts, 8080));
  CHECK_FALSE(web::host_allowed("localhost:8081", hosts, 8080));
  CHECK_FALSE(web::host_allowed("localhost", hosts, 8080));
  CHECK(web::host_allowed("localhost", hosts, 80));
  CHECK_FALSE(web::host_allowed("localhost:", hosts, 80));
  CHECK_FALSE(web::host_allowed("evil.example:8080", hosts, 8080));
  CHECK_FALSE(web::host_allowed("", hosts, 8080));
  CHECK(web::origin_matches("http://localhost:8080", "localhost:8080"));
  CHECK_FALSE(web::origin_matches("https://localhost:8080", "localhost:8080"));
  CHECK_FALSE(web::origin_matches("null", "localhost:8080"));
  CHECK_FALSE(web::origin_matches("http://evil.example", "localhost:8080"));

  CHECK(web::mime_type("a/index.html") == "text/html; charset=utf-8");
  CHECK(web::mime_type("app.JS") == "text/javascript; charset=utf-8");
  CHECK(web::mime_type("x.bin") == "application/octet-stream");
}

TEST_CASE("The page is served with the token in the query, then with the cookie it sets",
          "[io][web_server]") {
  Rig rig;
  HttpClient client(rig);
  const auto page = client.get("/?" + query_token());
  CHECK(page.result_int() == 200);
  CHECK(page.body() == "<p>index</p>");
  CHECK(page[http::field::content_type] == "text/html; charset=utf-8");
  CHECK(page[http::field::cache_control] == "no-store");
  CHECK(page[http::field::set_cookie] == rig.cookie() + "; Path=/; HttpOnly; SameSite=Strict");

  // The same connection (kept alive), with the cookie among others.
  const std::string cookie = "Cookie: theme=dark; " + rig.cookie() + "\r\n";
  const auto script = client.get("/app.js", cookie);
  CHECK(script.result_int() == 200);
  CHECK(script.body() == "let app;");
  CHECK(script[http::field::content_type] == "text/javascript; charset=utf-8");
  CHECK(script.find(http::field::set_cookie) == script.end());

  const std::vector<std::pair<std::string, std::string>> types{
      {"/style.css", "text/css; charset=utf-8"},
      {"/logo.png", "image/png"},
      {"/icon.svg", "image/svg+xml"},
      {"/data.json", "application/json"},
      {"/app.js.map", "application/json"},
      {"/index.html", "text/html; charset=utf-8"}};
  for (const auto& [target, type] : types) {
    const auto file = client.get(target, cookie);
    CHECK(file.result_int() == 200);
    CHECK(file[http::field::content_type] == type);
  }
  const auto library = client.get("/lib/three/three.module.js", cookie);
  CHECK(library.result_int() == 200);
  CHECK(library.body() == "export {}");
  CHECK(library[http::field::cache_control] == "private, max-age=3600");
  CHECK(client.get("/lib/chart.js/chart.js", cookie).body() == "chart");
  CHECK(client.get("/favicon.ico", cookie).result_int() == 204);

  // HEAD: the headers of a GET, no body.
  client.request("/app.js?" + query_token(), {}, "HEAD");
  const auto head = client.response(true);
  CHECK(head.result_int() == 200);
  CHECK(head[http::field::content_length] == "8");
  CHECK(client.get("/data.json", cookie).body() == "[]");  // nothing of a body came in between
}

TEST_CASE("Requests without the right token are refused", "[io][web_server]") {
  Rig rig;
  CHECK(status_of(rig, "/") == 403);
  CHECK(status_of(rig, "/app.js") == 403);
  CHECK(status_of(rig, "/?token=0123456789abcdef0123456789abcdee") == 403);
  CHECK(status_of(rig, "/?token=") == 403);
  CHECK(status_of(rig, "/?token=" + std::string(kToken) + "0") == 403);
  CHECK(status_of(rig, "/", "Cookie: dxlemu_token_1=" + std::string(kToken) + "\r\n") == 403);
  CHECK(status_of(rig, "/", "Cookie: " + rig.cookie() + "x\r\n") == 403);
  HttpClient client(rig);
  const auto refused = client.get("/");
  CHECK(refused.body().find("token") != std::string::npos);
  CHECK(refused.find(http::field::set_cookie) == refused.end());
  CHECK(client.get("/?" + query_token()).result_int() == 200);  // still open after a 403
}

TEST_CASE("Paths outside the web root and the two libraries are refused", "[io][web_server]") {
  Rig rig;
  const std::string cookie = "Cookie: " + rig.cookie() + "\r\n";
  CHECK(status_of(rig, "/../secret.txt", cookie) == 404);
  CHECK(status_of(rig, "/%2e%2e/secret.txt", cookie) == 404);
  CHECK(status_of(rig, "/lib/../secret.txt", cookie) == 404);
  CHECK(status_of(rig, "/lib/three/../../secret.txt", cookie) == 404);
  CHECK(status_of(rig, "/lib/jquery/jquery.js", cookie) == 404);
  CHECK(status_of(rig, "/lib/three/", cookie) == 404);
  CHECK(status_of(rig, "/lib/three", cookie) == 404);
  CHECK(status_of(rig, "//etc/passwd", cookie) == 404);
  CHECK(status_of(rig, "/.hidden", cookie) == 404);
  CHECK(status_of(rig, "/missing.js", cookie) == 404);
  CHECK(status_of(rig, "/app.js%00.png", cookie) == 400);
  CHECK(status_of(rig, "/..%5csecret.txt", cookie) == 400);
  CHECK(status_of(rig, "/%zz", cookie) == 400);
  CHECK(status_of(rig, "http://" + rig.host() + "/?" + query_token()) == 400);
  // Sanity: the files themselves are there.
  CHECK(fs::exists(rig.dir.path() / "secret.txt"));
  CHECK(status_of(rig, "/logo.png", cookie) == 200);
}

TEST_CASE("Only GET and HEAD without a body, and headers of at most 8 KiB", "[io][web_server]") {
  Rig rig;
  const std::string cookie = "Cookie: " + rig.cookie() + "\r\n";
  {
    HttpClient client(rig);
    client.request("/", cookie, "DELETE");
    const auto refused = client.response();
    CHECK(refused.result_int() == 405);
    CHECK(refused[http::field::allow] == "GET, HEAD");
    CHECK(client.get("/", cookie).result_int() == 200);  // no body: the connection stays
  }
  {
    HttpClient client(rig);
    client.request("/", cookie + "Content-Length: 5\r\n", "POST");
    client.write("hello");
    CHECK(client.response().result_int() == 405);
    CHECK(client.closed_by_server());
  }
  {
    HttpClient client(rig);
    client.request("/", cookie + "Content-Length: 5\r\n");
    client.write("hello");
    CHECK(client.response().result_int() == 413);
    CHECK(client.closed_by_server());
  }
  {
    HttpClient client(rig);
    client.request("/", cookie + "Transfer-Encoding: chunked\r\n");
    client.write("5\r\nhello\r\n0\r\n\r\n");
    CHECK(client.response().result_int() == 413);
    CHECK(client.closed_by_server());
  }
  {
    HttpClient client(rig);
    client.request("/", cookie + "X-Filler: " + std::string(9000, 'x') + "\r\n");
    CHECK(client.response().result_int() == 431);
    CHECK(client.closed_by_server());
  }
  {
    HttpClient client(rig);
    client.request("/", cookie + "X-Filler: " + std::string(7000, 'x') + "\r\n");
    CHECK(client.response().result_int() == 200);
  }
  {
    HttpClient client(rig);
    client.write("HELLO THERE\r\n\r\n");
    CHECK(client.response().result_int() == 400);
    CHECK(client.closed_by_server());
  }
}

TEST_CASE("Slow requests time out and connections beyond the limit are refused",
          "[io][web_server]") {
  Rig rig([](WebServerOptions& options) {
    options.request_timeout = std::chrono::milliseconds(100);
    options.max_connections = 2;
  });
  HttpClient idle(rig);
  idle.write("GET / HTTP/1.1\r\n");  // and never the rest
  HttpClient second(rig);
  settle(rig.io);
  CHECK(rig.server->connections() == 2);
  {
    HttpClient third(rig);
    const auto refused = third.response();
    CHECK(refused.result_int() == 503);
    CHECK(third.closed_by_server());
  }
  CHECK(idle.closed_by_server());    // after request_timeout
  CHECK(second.closed_by_server());  // an idle connection too
  CHECK(rig.server->connections() == 0);
  CHECK(status_of(rig, "/?" + query_token()) == 200);
}

TEST_CASE("A WebSocket carries request lines and their replies", "[io][web_server]") {
  Rig rig([](WebServerOptions& options) { options.first_session_id = 1000; });
  WsClient client(rig);
  REQUIRE(client.handshake() == 101);
  CHECK(rig.server->sessions() == 1);
  client.send("hello");
  CHECK(client.receive() == "HELLO");
  // Several lines in one message: each answered, empty lines and empty replies skipped, "\r"
  // before "\n" dropped.
  client.send("one\r\n\nquiet\ntwo\n");
  CHECK(client.receive_lines(2) == Lines{"ONE", "TWO"});
  client.send("throw\nid");
  CHECK(client.receive_lines(2) == Lines{"internal: boom", "1000"});
  // A message of exactly the limit is one line like any other.
  client.send(std::string(std::size_t{64} * 1024, 'a'));
  CHECK(client.receive() == std::string(std::size_t{64} * 1024, 'A'));

  // localhost is this server too.
  WsClient local(rig);
  CHECK(local.handshake("/ws?" + query_token(), "same",
                        "localhost:" + std::to_string(rig.server->port())) == 101);
  local.send("id");
  CHECK(local.receive() == "1001");
}

TEST_CASE("A WebSocket upgrade needs the token in its URL and this server's Host and Origin",
          "[io][web_server]") {
  Rig rig;
  const std::string port = std::to_string(rig.server->port());
  CHECK(WsClient(rig).handshake("/ws") == 403);
  CHECK(WsClient(rig).handshake("/ws", "same", {}, rig.cookie()) == 403);  // cookie alone
  CHECK(WsClient(rig).handshake("/ws?token=wrong") == 403);
  CHECK(WsClient(rig).handshake("/ws?" + query_token(), "") == 403);  // no Origin
  CHECK(WsClient(rig).handshake("/ws?" + query_token(), "http://evil.example") == 403);
  CHECK(WsClient(rig).handshake("/ws?" + query_token(), "https://" + rig.host()) == 403);
  CHECK(WsClient(rig).handshake("/ws?" + query_token(), "same", "evil.example:" + port) == 403);
  CHECK(WsClient(rig).handshake("/ws?" + query_token(), "same", "127.0.0.1:1") == 403);
  CHECK(WsClient(rig).handshake("/other?" + query_token()) == 404);
  CHECK(rig.server->sessions() == 0);
  CHECK(status_of(rig, "/ws?" + query_token()) == 400);  // not an upgrade
}

TEST_CASE("An oversize message closes with 1009, a binary one with 1003, bad UTF-8 with 1007",
          "[io][web_server]") {
  Rig rig([](WebServerOptions& options) { options.max_message = 1000; });
  WsClient big(rig);
  REQUIRE(big.handshake() == 101);
  big.send(std::string(1001, 'a'));
  CHECK(big.receive().empty());
  CHECK(big.error() == websocket::error::closed);
  CHECK(big.close_code() == websocket::close_code::too_big);

  WsClient binary(rig);
  REQUIRE(binary.handshake() == 101);
  binary.send("hello", true);
  CHECK(binary.receive().empty());
  CHECK(binary.error() == websocket::error::closed);
  CHECK(binary.close_code() == websocket::close_code::unknown_data);

  WsClient garbled(rig);
  REQUIRE(garbled.handshake() == 101);
  garbled.send("caf\xc3");  // not UTF-8
  CHECK(garbled.receive().empty());
  CHECK(garbled.error() == websocket::error::closed);
  CHECK(garbled.close_code() == websocket::close_code::bad_payload);

  REQUIRE(run_until(rig.io, [&] { return rig.closed.size() == 3; }));
  CHECK(rig.closed == std::vector<std::uint64_t>{1, 2, 3});
  CHECK(rig.server->sessions() == 0);
}

TEST_CASE("Events are gathered into few messages, in order with the replies", "[io][web_server]") {
  WebSession* subscriber = nullptr;
  Rig rig({}, [&](std::string_view line, WebSession& session) {
    subscriber = &session;
    return upper_case(line, session);
  });
  WsClient client(rig);
  REQUIRE(client.handshake() == 101);
  client.send("subscribe");
  CHECK(client.receive() == "SUBSCRIBE");
  REQUIRE(subscriber != nullptr);
  subscriber->send_event("e1");
  subscriber->send_event("e2");
  subscriber->send_event("e3");
  CHECK(client.receive() == "e1\ne2\ne3");
  // An event made before a reply goes out before it, with it.
  subscriber->send_event("before");
  client.send("request");
  CHECK(client.receive_lines(2) == Lines{"before", "REQUEST"});
  CHECK(subscriber->dropped_events() == 0);
  CHECK(rig.server->dropped_events() == 0);
}

TEST_CASE("A client that does not read loses its oldest events, never a reply",
          "[io][web_server]") {
  WebSession* subscriber = nullptr;
  Rig rig([](WebServerOptions& options) { options.max_queued_events = 8; },
          [&](std::string_view line, WebSession& session) {
            subscriber = &session;
            return upper_case(line, session);
          });
  WsClient slow(rig, 8192);
  REQUIRE(slow.handshake() == 101);
  slow.send("subscribe");
  CHECK(slow.receive() == "SUBSCRIBE");
  REQUIRE(subscriber != nullptr);
  // 64 KiB events until the kernel's buffers are full and the server's write stays unfinished:
  // then events are dropped.
  const std::string filler(std::size_t{64} * 1024, 'x');
  std::size_t sent = 0;
  for (; sent < 2000 && rig.server->dropped_events() == 0; ++sent) {
    subscriber->send_event("event " + std::to_string(sent) + " " + filler);
    settle(rig.io);
  }
  REQUIRE(rig.server->dropped_events() > 0);
  // Requests are still read, and their replies wait.
  slow.send("r1\nr2");
  slow.send("r3");
  for (int i = 0; i < 20; ++i, ++sent) {
    subscriber->send_event("event " + std::to_string(sent) + " " + filler);
  }
  subscriber->send_event("last");
  ++sent;
  settle(rig.io);
  const std::uint64_t dropped = rig.server->dropped_events();
  CHECK(dropped >= 20);
  CHECK(subscriber->dropped_events() == dropped);

  // Reading, the client gets every reply, the events not dropped in order, and notices that
  // add up to the events lost.
  Lines replies;
  std::uint64_t events = 0;
  std::uint64_t noticed = 0;
  std::uint64_t last_total = 0;
  std::int64_t previous = -1;
  bool last = false;
  while (!last || replies.size() < 3) {
    const std::string message = slow.receive();
    REQUIRE_FALSE(slow.error());
    for (const std::string& line : split_lines(message)) {
      if (line.rfind("event ", 0) == 0) {
        const std::int64_t number = std::stoll(line.substr(6));
        CHECK(number > previous);
        previous = number;
        ++events;
      } else if (line == "last") {
        last = true;
        ++events;
      } else if (line.rfind(R"({"event":"dropped","count":)", 0) == 0) {
        const auto json = nlohmann::json::parse(line);
        noticed += json.at("count").get<std::uint64_t>();
        last_total = json.at("total").get<std::uint64_t>();
        CHECK(last_total == noticed);
      } else {
        replies.push_back(line);
      }
    }
  }
  CHECK(replies == Lines{"R1", "R2", "R3"});
  CHECK(noticed == dropped);
  CHECK(last_total == dropped);
  CHECK(events + dropped == sent);
  CHECK(rig.closed.empty());
}

TEST_CASE("A client with many replies unread is read no more until it reads them",
          "[io][web_server]") {
  std::size_t requests = 0;
  const std::string big(std::size_t{256} * 1024, 'r');
  Rig rig({}, [&](std::string_view, WebSession&) {
    ++requests;
    return std::string(big);
  });
  WsClient client(rig, 8192);
  REQUIRE(client.handshake() == 101);
  // Requests until the kernel's buffers are full and over pause_reading_above of replies wait:
  // then a request stays unread.
  std::size_t sent = 0;
  while (sent < 800 && requests == sent) {
    client.send("more");
    ++sent;
    settle(rig.io);
  }
  REQUIRE(requests < sent);
  // A few more wait too.
  for (int i = 0; i < 4; ++i, ++sent) {
    client.send("more");
  }
  settle(rig.io);
  CHECK(requests < sent);
  // Reading the replies lets the server read the requests again, and every reply comes.
  std::size_t received = 0;
  while (received < sent) {
    received += client.receive().size() / big.size();
    REQUIRE_FALSE(client.error());
  }
  CHECK(requests == sent);
}

TEST_CASE("A client that leaves a write unfinished too long is closed", "[io][web_server]") {
  WebSession* subscriber = nullptr;
  Rig rig([](WebServerOptions& options) { options.write_timeout = std::chrono::milliseconds(50); },
          [&](std::string_view line, WebSession& session) {
            subscriber = &session;
            return upper_case(line, session);
          });
  WsClient stuck(rig, 8192);
  REQUIRE(stuck.handshake() == 101);
  stuck.send("subscribe");
  CHECK(stuck.receive() == "SUBSCRIBE");
  REQUIRE(subscriber != nullptr);
  const std::string filler(std::size_t{64} * 1024, 'x');
  for (int i = 0; i < 2000 && rig.closed.empty(); ++i) {
    subscriber->send_event(filler);
    rig.io.restart();
    rig.io.poll();
  }
  REQUIRE(run_until(rig.io, [&] { return !rig.closed.empty(); }));
  CHECK(rig.closed == std::vector<std::uint64_t>{1});
}

TEST_CASE("A client that vanishes mid-frame is forgotten without disturbing another",
          "[io][web_server]") {
  Rig rig;
  WsClient leaving(rig);
  WsClient staying(rig);
  REQUIRE(leaving.handshake() == 101);
  REQUIRE(staying.handshake() == 101);
  // A masked text frame announcing 100 bytes, with 10 of them.
  const std::string partial = std::string("\x81\xE4\x01\x02\x03\x04", 6) + "0123456789";
  boost::asio::write(leaving.socket(), boost::asio::buffer(partial));
  settle(rig.io);
  leaving.socket().close();
  REQUIRE(run_until(rig.io, [&] { return !rig.closed.empty(); }));
  CHECK(rig.closed == std::vector<std::uint64_t>{1});
  CHECK(rig.server->sessions() == 1);
  staying.send("still here");
  CHECK(staying.receive() == "STILL HERE");
}

TEST_CASE("The destructor closes every connection and reports each session", "[io][web_server]") {
  Rig rig;
  WsClient first(rig);
  WsClient second(rig);
  REQUIRE(first.handshake() == 101);
  REQUIRE(second.handshake() == 101);
  HttpClient page(rig);
  settle(rig.io);
  CHECK(rig.server->connections() == 3);
  rig.server.reset();
  CHECK(rig.closed == std::vector<std::uint64_t>{1, 2});
  CHECK(first.receive().empty());
  CHECK(page.closed_by_server());
}

TEST_CASE("The server's address, its URL and a port in use", "[io][web_server]") {
  Rig rig;
  const std::string port = std::to_string(rig.server->port());
  CHECK(rig.server->port() != 0);
  CHECK(rig.server->loopback());
  CHECK(rig.server->url() == "http://127.0.0.1:" + port + "/?token=" + std::string(kToken));

  WebServerOptions options;
  options.token = "t";
  options.port = rig.server->port();
  const WebServer::Replies replies{[](std::string_view) { return std::string(); }};
  CHECK_THROWS_WITH(WebServer(rig.io, options, upper_case, replies),
                    Catch::Contains("127.0.0.1:" + port) && Catch::Contains("in use"));
  options.address = "not an address";
  CHECK_THROWS_WITH(WebServer(rig.io, options, upper_case, replies),
                    Catch::Contains("not an address"));
  options.address = "127.0.0.1";
  options.port = 0;
  options.token.clear();
  CHECK_THROWS_AS(WebServer(rig.io, options, upper_case, replies), std::invalid_argument);

  options.token = "t";
  options.address = "0.0.0.0";
  const WebServer any(rig.io, options, upper_case, replies);
  CHECK(any.url() == "http://127.0.0.1:" + std::to_string(any.port()) + "/?token=t");
  CHECK_FALSE(any.loopback());
  options.address = "[::1]";
  try {
    const WebServer six(rig.io, options, upper_case, replies);
    CHECK(six.url() == "http://[::1]:" + std::to_string(six.port()) + "/?token=t");
    CHECK(six.loopback());
  } catch (const std::system_error&) {
    WARN("no IPv6 loopback here: its URL is not checked");
  }
}

}  // namespace dxlemu::web_server_test
