// The web server: listening, the HTTP connections (the page's files, the token, the upgrade to
// a WebSocket) and the table of WebSocket sessions. The rules of who may do what are in
// io/web_access.*, which files are served in io/web_files.*, and the API's traffic over a
// WebSocket in io/web_socket_session.*.
#include "io/web_server.hpp"

#include <array>
#include <boost/asio/buffer.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core/error.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/empty_body.hpp>
#include <boost/beast/http/error.hpp>
#include <boost/beast/http/file_body.hpp>
#include <boost/beast/http/parser.hpp>
#include <boost/beast/http/read.hpp>
#include <boost/beast/http/string_body.hpp>
#include <boost/beast/http/write.hpp>
#include <boost/beast/websocket/rfc6455.hpp>
#include <map>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>

#include "io/accept_again.hpp"
#include "io/session_table.hpp"
#include "io/web_access.hpp"
#include "io/web_files.hpp"
#include "io/web_socket_session.hpp"

namespace dxlemu::io {

namespace beast = boost::beast;
namespace http = boost::beast::http;
namespace websocket = boost::beast::websocket;
using tcp = boost::asio::ip::tcp;

struct WebServer::State final : web::WebSocketOwner, std::enable_shared_from_this<State> {
  class HttpConnection;

  // The request line and headers of one request at most (431 beyond).
  static constexpr std::uint32_t kHeaderLimit = 8 * 1024;
  // After a response that ends a connection, what the client still sends is read and dropped
  // for this long, so that closing with unread bytes (a TCP reset) does not destroy the
  // response before the client has read it.
  static constexpr std::chrono::seconds kLinger{1};
  // What a connection beyond max_connections gets, written without waiting.
  static constexpr std::string_view kTooManyConnections =
      "HTTP/1.1 503 Service Unavailable\r\nServer: dxlemu\r\nContent-Type: text/plain\r\n"
      "Content-Length: 37\r\nConnection: close\r\n\r\ntoo many connections to the web page\n";
  // Cache-Control of what may change from one run to the next (the page, every refusal), and
  // of Debian's libraries (the same until a package upgrade).
  static constexpr std::string_view kNoStore = "no-store";
  static constexpr std::string_view kLibraryCaching = "private, max-age=3600";

  /// The address to listen on: numeric, "[v6]" or "localhost".
  static boost::asio::ip::address parse_address(std::string text);
  /// Beast's string views (Boost's, in Boost 1.74) and the standard's.
  static std::string_view std_view(beast::string_view text) { return {text.data(), text.size()}; }
  static beast::string_view beast_view(std::string_view text) { return {text.data(), text.size()}; }

  State(boost::asio::io_context& io, WebServerOptions options, Handler handler, Replies replies);

  std::string answer(std::string_view line, WebSession& session) override;
  void close(web::WebSocketSession& session) override;
  void count_dropped(std::uint64_t count) override { dropped += count; }

  void accept();
  /// Hands `connection`'s stream to a new WebSocket session for `upgrade` (already checked).
  void upgrade(HttpConnection& connection, beast::tcp_stream stream,
               const http::request<http::empty_body>& request);
  /// Why a WebSocket upgrade is refused, or nothing when it is not.
  std::optional<std::string> upgrade_refusal(const http::request<http::empty_body>& request,
                                             bool token_in_query, const tcp::endpoint& local) const;
  /// Closes an HTTP connection and forgets it.
  void forget(HttpConnection& connection);
  /// Closes everything (the server's destructor).
  void stop();

  boost::asio::io_context& io;
  std::shared_ptr<const WebServerOptions> options;
  Handler handler;
  Replies replies;
  tcp::acceptor acceptor;
  boost::asio::steady_timer retry_timer;
  boost::asio::ip::address address;
  std::uint16_t port = 0;
  std::string cookie_name;
  // Host header names a WebSocket upgrade may carry (with the port), besides the address the
  // client reached us at: what a browser on this machine would put there for a loopback or
  // the listening address. A name that resolves to us via DNS is refused (DNS rebinding).
  std::vector<std::string> hosts;
  std::uint64_t next_session_id;
  std::uint64_t next_connection_id = 1;
  std::map<std::uint64_t, std::shared_ptr<HttpConnection>> connections;
  SessionTable<web::WebSocketSession, WebSession> sessions;
  std::uint64_t dropped = 0;
  bool stopped = false;
};

/// One HTTP connection, until it closes or becomes a WebSocket session. Owned by the State's
/// `connections` and by its pending I/O handlers.
class WebServer::State::HttpConnection : public std::enable_shared_from_this<HttpConnection> {
 public:
  HttpConnection(std::weak_ptr<State> state, tcp::socket socket, std::uint64_t id)
      : state_(std::move(state)), stream_(std::move(socket)), id_(id) {}

  void start() { read_request(); }
  std::uint64_t id() const { return id_; }
  /// Closes the socket (pending operations complete as aborted); false if closed already.
  bool shut();

 private:
  void read_request();
  void on_request(const beast::error_code& ec);
  void answer(State& state);
  void serve_file(const web::FileLookup& lookup);
  /// Headers every response gets.
  template <typename Body>
  void decorate(http::response<Body>& response, std::string_view caching) const;
  /// A short text response (an error, or a 204 without body).
  void send_text(http::status status, std::string_view text, bool close_after = false);
  template <typename Body>
  void send(std::shared_ptr<http::response<Body>> response, bool close_after);
  /// Ends the connection once the response is out (see kLinger).
  void linger();
  void close_self();

  std::weak_ptr<State> state_;
  beast::tcp_stream stream_;
  std::uint64_t id_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::empty_body>> parser_;
  std::shared_ptr<void> response_;  // the response being written
  // Of the request being answered.
  unsigned version_ = 11;
  bool keep_alive_ = true;
  bool head_ = false;
  bool set_cookie_ = false;
  bool closed_ = false;
};

WebServer::State::State(boost::asio::io_context& io, WebServerOptions options_in, Handler handler,
                        Replies replies)
    : io(io),
      options(std::make_shared<const WebServerOptions>(std::move(options_in))),
      handler(std::move(handler)),
      replies(std::move(replies)),
      acceptor(io),
      retry_timer(io),
      next_session_id(options->first_session_id),
      sessions(io) {
  if (options->token.empty()) {
    throw std::invalid_argument("the web server needs a token");
  }
  address = parse_address(options->address);
  const std::string what = "the web server's address " + web::url_host(address.to_string()) + ":" +
                           std::to_string(options->port);
  const tcp::endpoint endpoint(address, options->port);
  boost::system::error_code ec;
  acceptor.open(endpoint.protocol(), ec);
  throw_if_failed(ec, "opening " + what);
  // A restarted daemon gets its port back at once, though the last one's connections linger in
  // TIME_WAIT; a port another socket listens on is still refused.
  acceptor.set_option(tcp::acceptor::reuse_address(true), ec);
  throw_if_failed(ec, "setting up " + what);
  acceptor.bind(endpoint, ec);
  throw_if_failed(ec, "binding " + what);
  acceptor.listen(boost::asio::socket_base::max_listen_connections, ec);
  throw_if_failed(ec, "listening on " + what);
  port = acceptor.local_endpoint().port();
  cookie_name = web::token_cookie_name(port);
  hosts = {"localhost", "127.0.0.1", "[::1]", web::url_host(address.to_string())};
}

boost::asio::ip::address WebServer::State::parse_address(std::string text) {
  if (text.size() >= 2 && text.front() == '[' && text.back() == ']') {
    text = text.substr(1, text.size() - 2);
  }
  if (text == "localhost") {
    text = "127.0.0.1";
  }
  boost::system::error_code ec;
  auto parsed = boost::asio::ip::make_address(text, ec);
  throw_if_failed(ec, "the web server's address \"" + text + "\" (a numeric IPv4 or IPv6 address)");
  return parsed;
}

// A handler documented not to throw that throws anyway gets the internal_error reply.
std::string WebServer::State::answer(std::string_view line, WebSession& session) {
  try {
    return handler(line, session);
  } catch (const std::exception& e) {
    return replies.internal_error(e.what());
  } catch (...) {
    return replies.internal_error("unknown exception");
  }
}

void WebServer::State::accept() {
  acceptor.async_accept(
      [weak = weak_from_this()](const boost::system::error_code& ec, tcp::socket socket) {
        const auto self = weak.lock();
        if (!self || self->stopped) {
          return;
        }
        if (ec) {
          accept_again_later(self->retry_timer, weak);
          return;
        }
        if (self->connections.size() + self->sessions.size() >= self->options->max_connections) {
          // A fresh socket's buffer takes the short answer whole; no need to wait for it.
          boost::system::error_code ignored;
          socket.non_blocking(true, ignored);
          socket.write_some(boost::asio::buffer(kTooManyConnections), ignored);
          socket.shutdown(tcp::socket::shutdown_both, ignored);
          socket.close(ignored);
        } else {
          const std::uint64_t id = self->next_connection_id++;
          auto connection = std::make_shared<HttpConnection>(weak, std::move(socket), id);
          self->connections.emplace(id, connection);
          connection->start();
        }
        self->accept();
      });
}

std::optional<std::string> WebServer::State::upgrade_refusal(
    const http::request<http::empty_body>& request, bool token_in_query,
    const tcp::endpoint& local) const {
  // The page always knows the token; the cookie alone would also come with a request that
  // another site's page makes (SameSite aside), so the WebSocket wants it in the URL.
  if (!token_in_query) {
    return "forbidden: the WebSocket needs the token in its URL (/ws?token=...)\n";
  }
  const std::string_view host = std_view(request[http::field::host]);
  std::vector<std::string> allowed = hosts;
  allowed.push_back(web::url_host(local.address().to_string()));
  if (!web::host_allowed(host, allowed, port)) {
    return "forbidden: the Host header \"" + std::string(host) +
           "\" is not this server's address (use " + web::url_host(address.to_string()) + ":" +
           std::to_string(port) + " or localhost:" + std::to_string(port) + ")\n";
  }
  const std::string_view origin = std_view(request[http::field::origin]);
  if (origin.empty()) {
    return std::string("forbidden: a WebSocket upgrade needs an Origin header\n");
  }
  if (!web::origin_matches(origin, host)) {
    return "forbidden: the Origin \"" + std::string(origin) + "\" is not this server's page\n";
  }
  return std::nullopt;
}

void WebServer::State::upgrade(HttpConnection& connection, beast::tcp_stream stream,
                               const http::request<http::empty_body>& request) {
  connections.erase(connection.id());
  const std::uint64_t id = next_session_id++;
  auto session =
      std::make_shared<web::WebSocketSession>(weak_from_this(), std::move(stream), id, options);
  sessions.add(session);
  session->start(request);
}

void WebServer::State::forget(HttpConnection& connection) {
  connection.shut();
  connections.erase(connection.id());
}

void WebServer::State::close(web::WebSocketSession& session) {
  // on_close typically erases from a subscriber list that send_event() may be iterating now:
  // the table reports from a handler of its own.
  sessions.close(session);
}

void WebServer::State::stop() {
  stopped = true;
  boost::system::error_code ignored;
  acceptor.close(ignored);
  retry_timer.cancel();
  for (auto& [id, connection] : connections) {
    connection->shut();
  }
  connections.clear();
  sessions.close_all();
}

bool WebServer::State::HttpConnection::shut() {
  if (closed_) {
    return false;
  }
  closed_ = true;
  stream_.close();
  return true;
}

void WebServer::State::HttpConnection::close_self() {
  if (const auto state = state_.lock()) {
    state->forget(*this);
  } else {
    shut();
  }
}

void WebServer::State::HttpConnection::read_request() {
  const auto state = state_.lock();
  if (!state || closed_) {
    return;
  }
  parser_.emplace();
  parser_->header_limit(kHeaderLimit);
  // Also the limit on an idle keep-alive connection waiting for its next request.
  stream_.expires_after(state->options->request_timeout);
  // Only the header: a body is refused, never read.
  http::async_read_header(stream_, buffer_, *parser_,
                          [self = shared_from_this()](const beast::error_code& ec, std::size_t) {
                            self->on_request(ec);
                          });
}

void WebServer::State::HttpConnection::on_request(const beast::error_code& ec) {
  const auto state = state_.lock();
  if (!state || state->stopped || closed_) {
    return;
  }
  if (ec == http::error::header_limit) {
    send_text(http::status::request_header_fields_too_large,
              "request header fields too large (at most 8 KiB)\n", true);
    return;
  }
  // Any other error of the parser is a malformed request; end_of_stream (closed between
  // requests), partial_message (closed within one), a timeout or a socket error end it quietly.
  if (ec && ec.category() == http::make_error_code(http::error::bad_method).category() &&
      ec != http::error::end_of_stream && ec != http::error::partial_message) {
    send_text(http::status::bad_request, "bad request: " + ec.message() + "\n", true);
    return;
  }
  if (ec) {
    close_self();
    return;
  }
  answer(*state);
}

void WebServer::State::HttpConnection::answer(State& state) {
  const http::request<http::empty_body>& request = parser_->get();
  version_ = request.version();
  keep_alive_ = request.keep_alive();
  head_ = request.method() == http::verb::head;
  set_cookie_ = false;
  // A body would have to be read past to get to the next request: the connection ends instead.
  const bool has_body = !parser_->is_done();
  if (request.method() != http::verb::get && !head_) {
    send_text(http::status::method_not_allowed, "only GET and HEAD are served\n", has_body);
    return;
  }
  if (has_body) {
    send_text(http::status::payload_too_large, "a request body is not accepted\n", true);
    return;
  }
  const std::optional<web::Target> target = web::split_target(std_view(request.target()));
  if (!target) {
    send_text(http::status::bad_request, "bad request: the target is not a path\n", true);
    return;
  }
  const std::optional<std::string> query_token = web::query_value(target->query, "token");
  const bool token_in_query = query_token && web::same_secret(*query_token, state.options->token);
  bool token_in_cookie = false;
  for (auto [field, end] = request.equal_range(http::field::cookie); field != end; ++field) {
    for (const std::string_view value :
         web::cookie_values(std_view(field->value()), state.cookie_name)) {
      token_in_cookie = token_in_cookie || web::same_secret(value, state.options->token);
    }
  }
  if (!token_in_query && !token_in_cookie) {
    send_text(http::status::forbidden,
              "forbidden: this page needs the token that `dxlemu run --web` printed: open the "
              "address it gave (http://.../?token=...)\n");
    return;
  }
  // The page's assets then come with the cookie, without the token in their URLs.
  set_cookie_ = token_in_query;
  const bool is_upgrade = websocket::is_upgrade(request);
  if (target->path == "/ws") {
    if (!is_upgrade) {
      send_text(http::status::bad_request,
                "bad request: /ws is the control API's WebSocket: it needs an Upgrade\n", true);
      return;
    }
    beast::error_code ignored;
    const tcp::endpoint local = stream_.socket().local_endpoint(ignored);
    if (const auto refusal = state.upgrade_refusal(request, token_in_query, local)) {
      send_text(http::status::forbidden, *refusal, true);
      return;
    }
    closed_ = true;  // the stream is the session's from now on
    state.upgrade(*this, std::move(stream_), request);
    return;
  }
  if (is_upgrade) {
    send_text(http::status::not_found, "not found: the WebSocket is at /ws\n", true);
    return;
  }
  if (target->path == "/favicon.ico") {
    send_text(http::status::no_content, {});  // the page declares its icon inline
    return;
  }
  const web::FileLookup lookup =
      web::resolve_file(target->path, state.options->web_root, state.options->library_root);
  if (lookup.status != 200) {
    send_text(static_cast<http::status>(lookup.status), lookup.reason + "\n", lookup.status == 400);
    return;
  }
  serve_file(lookup);
}

void WebServer::State::HttpConnection::serve_file(const web::FileLookup& lookup) {
  http::file_body::value_type body;
  beast::error_code ec;
  body.open(lookup.file.c_str(), beast::file_mode::scan, ec);
  if (ec) {
    send_text(http::status::not_found, "not found\n");
    return;
  }
  const std::string_view caching =
      lookup.area == web::FileArea::Library ? kLibraryCaching : kNoStore;
  const std::string_view type = web::mime_type(lookup.file);
  if (head_) {
    auto response = std::make_shared<http::response<http::empty_body>>(http::status::ok, version_);
    decorate(*response, caching);
    response->set(http::field::content_type, beast_view(type));
    response->content_length(body.size());
    send(std::move(response), false);
    return;
  }
  const std::uint64_t size = body.size();
  auto response = std::make_shared<http::response<http::file_body>>(
      std::piecewise_construct, std::make_tuple(std::move(body)),
      std::make_tuple(http::status::ok, version_));
  decorate(*response, caching);
  response->set(http::field::content_type, beast_view(type));
  response->content_length(size);
  send(std::move(response), false);
}

template <typename Body>
void WebServer::State::HttpConnection::decorate(http::response<Body>& response,
                                                std::string_view caching) const {
  response.set(http::field::server, "dxlemu");
  response.set(http::field::cache_control, beast_view(caching));
  response.set("X-Content-Type-Options", "nosniff");
  // The page's address holds the token: never pass it on to another site.
  response.set("Referrer-Policy", "no-referrer");
  if (set_cookie_) {
    if (const auto state = state_.lock()) {
      response.set(http::field::set_cookie, web::token_cookie(state->port, state->options->token));
    }
  }
  response.keep_alive(keep_alive_);
}

void WebServer::State::HttpConnection::send_text(http::status status, std::string_view text,
                                                 bool close_after) {
  auto response = std::make_shared<http::response<http::string_body>>(status, version_);
  decorate(*response, kNoStore);
  if (!text.empty()) {
    response->set(http::field::content_type, "text/plain; charset=utf-8");
  }
  if (status == http::status::method_not_allowed) {
    response->set(http::field::allow, "GET, HEAD");
  }
  if (close_after) {
    response->keep_alive(false);
  }
  if (status != http::status::no_content) {
    response->content_length(text.size());
    if (!head_) {
      response->body().assign(text);
    }
  }
  send(std::move(response), close_after);
}

template <typename Body>
void WebServer::State::HttpConnection::send(std::shared_ptr<http::response<Body>> response,
                                            bool close_after) {
  const auto state = state_.lock();
  if (!state || closed_) {
    return;
  }
  const bool close = close_after || response->need_eof();
  stream_.expires_after(state->options->request_timeout);
  http::async_write(stream_, *response,
                    [self = shared_from_this(), close](const beast::error_code& ec, std::size_t) {
                      self->response_.reset();
                      if (ec) {
                        self->close_self();
                      } else if (close) {
                        self->linger();
                      } else {
                        self->read_request();
                      }
                    });
  response_ = std::move(response);
}

void WebServer::State::HttpConnection::linger() {
  if (closed_) {
    return;
  }
  beast::error_code ignored;
  stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
  stream_.expires_after(kLinger);
  buffer_.consume(buffer_.size());
  struct Drain {
    std::shared_ptr<HttpConnection> self;
    void operator()(const beast::error_code& ec, std::size_t) const {
      if (ec || self->closed_) {
        self->close_self();
        return;
      }
      self->buffer_.consume(self->buffer_.size());
      self->stream_.async_read_some(self->buffer_.prepare(4096), Drain{self});
    }
  };
  stream_.async_read_some(buffer_.prepare(4096), Drain{shared_from_this()});
}

WebServer::WebServer(boost::asio::io_context& io, WebServerOptions options, Handler handler,
                     Replies replies)
    : state_(
          std::make_shared<State>(io, std::move(options), std::move(handler), std::move(replies))) {
  state_->accept();
}

WebServer::~WebServer() {
  state_->stop();
}

std::uint16_t WebServer::port() const {
  return state_->port;
}

std::string WebServer::url() const {
  std::string host = web::url_host(state_->address.to_string());
  if (state_->address.is_unspecified()) {
    host = state_->address.is_v4() ? "127.0.0.1" : "[::1]";
  }
  return "http://" + host + ":" + std::to_string(state_->port) +
         "/?token=" + state_->options->token;
}

bool WebServer::loopback() const {
  const auto& address = state_->address;
  return address.is_loopback() ||
         (address.is_v6() && address.to_v6().is_v4_mapped() &&
          boost::asio::ip::make_address_v4(boost::asio::ip::v4_mapped, address.to_v6())
              .is_loopback());
}

void WebServer::on_close(std::function<void(WebSession&)> callback) {
  state_->sessions.on_close(std::move(callback));
}

std::size_t WebServer::sessions() const {
  return state_->sessions.size();
}

std::size_t WebServer::connections() const {
  return state_->connections.size() + state_->sessions.size();
}

std::uint64_t WebServer::dropped_events() const {
  return state_->dropped;
}

}  // namespace dxlemu::io
