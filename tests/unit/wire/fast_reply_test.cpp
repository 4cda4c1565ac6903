// The Fast Sync/Bulk Read reply's layout as the bus sends it: LENGTH's limit, and the packet cut
// short when the chain of devices broke (protocol2.md "Fast Sync Read (0x8A)").
#include <catch2/catch.hpp>

#include "wire/packet_encoder.hpp"

using namespace dxlemu;
using Bytes = std::vector<std::uint8_t>;

TEST_CASE("A Fast reply's LENGTH counts the instruction byte and every block", "[wire][fast]") {
  const std::vector<std::size_t> two = {4, 2};
  CHECK(wire::fast_reply_length(two) == 1 + (4 + 4) + (4 + 2));
  CHECK(wire::fast_reply_length(std::vector<std::size_t>{}) == 1);
  // 65535 is the largest LENGTH: one byte less of data fits, one byte more does not.
  const std::vector<std::size_t> largest = {65535 - 1 - 4};
  const std::vector<std::size_t> too_long = {65535 - 1 - 4 + 1};
  CHECK(wire::fast_reply_length(largest) == 65535);
  CHECK(wire::fast_reply_length(too_long) == std::nullopt);
}

TEST_CASE("A Fast reply cut after its first devices keeps LENGTH and stops after their blocks",
          "[wire][fast]") {
  const wire::FastReply reply{{{0x00, 1, {0x11, 0x12}}, {0x00, 2, {0x21, 0x22}}}};
  const Bytes whole = wire::encode_fast_reply(reply);
  CHECK(wire::encode_fast_reply(reply, 2) == whole);
  const Bytes cut = wire::encode_fast_reply(reply, 1);
  // Header (4), ID, LENGTH (2), 0x55, then the first block: error, ID, 2 data bytes, CRC (2).
  REQUIRE(cut.size() == 8 + 6);
  CHECK(Bytes(whole.begin(), whole.begin() + 14) == cut);
  const Bytes head_only = wire::encode_fast_reply(reply, 0);
  CHECK(head_only == Bytes(whole.begin(), whole.begin() + 8));
}
