#include "io/wake_lead.hpp"

#include <catch2/catch.hpp>

#include <chrono>

namespace {

using dxlemu::io::WakeLead;
using std::chrono::microseconds;

}  // namespace

TEST_CASE("The wake lead is its maximum until a window of wake-ups was seen", "[sim]") {
  WakeLead lead(0.5, microseconds(200));
  for (std::size_t i = 0; i + 1 < WakeLead::kWindow; ++i) {
    lead.add(microseconds(40));
  }
  CHECK(lead.lead() == microseconds(200));
  lead.add(microseconds(40));
  CHECK(lead.lead() == microseconds(40));
}

TEST_CASE("The wake lead is the asked quantile of the recent wake-ups", "[sim]") {
  WakeLead median(0.5, microseconds(200));
  WakeLead p90(0.9, microseconds(200));
  // 64 wake-ups late by 1 ~ 64 µs.
  for (std::size_t i = 1; i <= WakeLead::kWindow; ++i) {
    median.add(microseconds(i));
    p90.add(microseconds(i));
  }
  CHECK(median.lead() == microseconds(33));  // rank round(0.5 * 63) = 32 of 0..63
  CHECK(p90.lead() == microseconds(58));     // rank round(0.9 * 63) = 57
}

TEST_CASE("The wake lead follows a machine whose wake-ups get later, up to its maximum", "[sim]") {
  WakeLead lead(0.5, microseconds(200));
  for (std::size_t i = 0; i < WakeLead::kWindow; ++i) {
    lead.add(microseconds(30));
  }
  CHECK(lead.lead() == microseconds(30));
  // Load arrives: wake-ups now come 120 µs late; once most of the window says so, so does the
  // lead.
  for (std::size_t i = 0; i < WakeLead::kWindow; ++i) {
    lead.add(microseconds(120));
  }
  CHECK(lead.lead() == microseconds(120));
  for (std::size_t i = 0; i < WakeLead::kWindow; ++i) {
    lead.add(std::chrono::milliseconds(3));
  }
  CHECK(lead.lead() == microseconds(200));  // never more: a longer spin would cost the client
  // Early wake-ups (negative lateness) count as punctual.
  for (std::size_t i = 0; i < WakeLead::kWindow; ++i) {
    lead.add(microseconds(-5));
  }
  CHECK(lead.lead() == microseconds(0));
}
