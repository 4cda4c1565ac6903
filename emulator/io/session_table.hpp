#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/post.hpp>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <utility>
#include <vector>

namespace dxlemu::io {

/// The open sessions of a server (the control socket's, the web's WebSockets) and how their
/// closing is reported. `Session` has `std::uint64_t id() const` and `bool shut()` (closes it;
/// false when it was closed already); `on_close` gets it as a `Base&`.
///
/// A close is reported from an io_context handler of its own, never from inside the handler or
/// the send that closed it: on_close typically erases from a subscriber list that a send may be
/// iterating right then (an event to a client that stopped reading).
template <typename Session, typename Base>
class SessionTable {
 public:
  explicit SessionTable(boost::asio::io_context& io)
      : io_(io), closed_(std::make_shared<Closed>()) {}

  /// Called once for each session that closes, after it has been shut.
  void on_close(std::function<void(Base&)> callback) { closed_->on_close = std::move(callback); }
  /// Keeps `session` as open.
  void add(std::shared_ptr<Session> session) {
    const std::uint64_t id = session->id();
    open_.emplace(id, std::move(session));
  }
  /// Sessions open now.
  std::size_t size() const { return open_.size(); }

  /// Shuts `session` and reports it to on_close soon; nothing when it was shut already.
  void close(Session& session) {
    if (!session.shut()) {
      return;
    }
    const auto found = open_.find(session.id());
    if (found == open_.end()) {
      return;
    }
    closed_->waiting.push_back(std::move(found->second));
    open_.erase(found);
    if (closed_->waiting.size() == 1) {
      boost::asio::post(io_, [weak = std::weak_ptr<Closed>(closed_)] {
        if (const auto closed = weak.lock()) {
          closed->report();
        }
      });
    }
  }

  /// Shuts every session and reports each to on_close now (the server's destructor); a report
  /// still posted then does nothing.
  void close_all() {
    for (auto& [id, session] : open_) {
      session->shut();
      closed_->waiting.push_back(std::move(session));
    }
    open_.clear();
    closed_->report();
    closed_->stopped = true;
  }

 private:
  /// What a posted report needs, apart from the table, so that it outlives neither.
  struct Closed {
    std::function<void(Base&)> on_close;
    std::vector<std::shared_ptr<Session>> waiting;  // shut, with on_close not yet called
    bool stopped = false;

    void report() {
      if (stopped) {
        return;
      }
      const auto sessions = std::exchange(waiting, {});
      for (const auto& session : sessions) {
        if (on_close) {
          on_close(*session);
        }
      }
    }
  };

  boost::asio::io_context& io_;
  std::map<std::uint64_t, std::shared_ptr<Session>> open_;
  std::shared_ptr<Closed> closed_;
};

}  // namespace dxlemu::io
