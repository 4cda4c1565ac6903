#include "io/realtime_driver.hpp"

namespace dxlemu::io {

RealTimeDriver::RealTimeDriver(boost::asio::io_context& io, sim::Scheduler& scheduler, Pace pace)
    : scheduler_(scheduler), pace_(pace), timer_(io), start_(std::chrono::steady_clock::now()) {}

sim::SimTime RealTimeDriver::wall_now() const {
  return sim::SimTime{
      std::chrono::duration_cast<sim::SimDuration>(std::chrono::steady_clock::now() - start_)};
}

void RealTimeDriver::catch_up() {
  scheduler_.advance_to(pace_ == Pace::WallClock ? wall_now() : scheduler_.now());
}

void RealTimeDriver::rearm() {
  const auto deadline = scheduler_.next_deadline();
  if (!deadline || (pace_ == Pace::Manual && *deadline > scheduler_.now())) {
    timer_.cancel();  // in manual time a future event waits for the clock to be stepped
    return;
  }
  // Manual time: the deadline is the present, and the timer (set in the past) fires at once.
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
