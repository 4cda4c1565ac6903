#pragma once

#include <chrono>

namespace dxlemu::io {

/// How long this machine's kernel takes to hand bytes across a pseudo-terminal, both ways: the
/// first quartile (at most 60 µs), over `samples` round trips on a private PTY pair, of writing a
/// 14-byte packet to the slave side and reading it on the master, then the same back
/// (docs/timing.md "PTY hand-over"). A real serial line has no such delay; the daemon subtracts it
/// from the arrival time of the client's bytes so that replies reach the client at their modelled
/// time. Takes about samples × 0.3 ms. Returns zero when no PTY can be opened.
std::chrono::nanoseconds measure_pty_handover(int samples = 64);

}  // namespace dxlemu::io
