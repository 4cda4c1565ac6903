#pragma once

#include <boost/asio/steady_timer.hpp>
#include <boost/system/error_code.hpp>
#include <chrono>
#include <memory>
#include <string>
#include <system_error>

namespace dxlemu::io {

/// Throws std::system_error for `ec`, `what` naming what failed ("binding 127.0.0.1:8080");
/// nothing when `ec` is no error. Boost's system category carries errno values on POSIX.
inline void throw_if_failed(const boost::system::error_code& ec, const std::string& what) {
  if (ec) {
    throw std::system_error(ec.value(), std::system_category(), what);
  }
}

/// How long a server waits before accepting again after accept() itself failed (EMFILE: out of
/// file descriptors, say). Retrying at once would spin, as the listening socket stays readable.
inline constexpr std::chrono::milliseconds kAcceptRetry{100};

/// Calls `state->accept()` once kAcceptRetry has passed on `timer`, unless the server's state is
/// gone or `stopped` by then (a server's State: `accept()` and a `stopped` flag).
template <typename State>
void accept_again_later(boost::asio::steady_timer& timer, std::weak_ptr<State> state) {
  timer.expires_after(kAcceptRetry);
  timer.async_wait([state = std::move(state)](const boost::system::error_code& ec) {
    const auto self = state.lock();
    if (!ec && self && !self->stopped) {
      self->accept();
    }
  });
}

}  // namespace dxlemu::io
