#include "io/realtime_driver.hpp"

namespace dxlemu::io {

RealTimeDriver::RealTimeDriver(boost::asio::io_context& io, sim::Scheduler& scheduler)
    : scheduler_(scheduler), timer_(io), start_(std::chrono::steady_clock::now()) {}

sim::SimTime RealTimeDriver::wall_now() const {
  return sim::SimTime{
      std::chrono::duration_cast<sim::SimDuration>(std::chrono::steady_clock::now() - start_)};
}

void RealTimeDriver::catch_up() {
  scheduler_.advance_to(wall_now());
}

void RealTimeDriver::rearm() {
  const auto deadline = scheduler_.next_deadline();
  if (!deadline) {
    timer_.cancel();
    return;
  }
  timer_.expires_at(start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                 deadline->time_since_epoch()));
  timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec) {
      return;  // re-armed or shut down
    }
    catch_up();
    rearm();
  });
}

}  // namespace dxlemu::io
