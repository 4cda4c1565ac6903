// What a group read asks of each device, before any servo is looked at.
#include <catch2/catch.hpp>

#include "bus/read_request.hpp"

using namespace dxlemu;

TEST_CASE("A Bulk Read's request keeps each ID's first part, in list order", "[bus][group]") {
  const wire::InstructionPacket packet{wire::Protocol::V2, wire::kBroadcastId,
                                       wire::BulkRead{{{3, 132, 4}, {1, 126, 2}, {3, 116, 4}}}};
  const bus::ReadRequest request = bus::read_request(packet);
  CHECK_FALSE(request.fast);
  CHECK_FALSE(request.v1_bulk);
  REQUIRE(request.parts.size() == 2);
  CHECK(request.parts[0].id == 3);
  CHECK(request.parts[0].address == 132);
  CHECK(request.parts[1].id == 1);
  CHECK(request.parts[1].length == 2);
}

TEST_CASE("Fast and Protocol 1.0 group reads are told apart", "[bus][group]") {
  wire::FastSyncRead fast;
  fast.address = 132;
  fast.length = 4;
  fast.ids = {1, 2, 1};
  const bus::ReadRequest f = bus::read_request({wire::Protocol::V2, wire::kBroadcastId, fast});
  CHECK(f.fast);
  CHECK(f.parts.size() == 2);
  const bus::ReadRequest v1 =
      bus::read_request({wire::Protocol::V1, wire::kBroadcastId, wire::BulkRead{{{1, 36, 2}}}});
  CHECK(v1.v1_bulk);
  CHECK_FALSE(v1.fast);
  CHECK(bus::read_request({wire::Protocol::V2, 1, wire::Ping{}}).parts.empty());
}

TEST_CASE("Group instructions are the Sync and Bulk ones and their Fast forms", "[bus][group]") {
  CHECK(bus::is_group_instruction(wire::Protocol::V2,
                                  wire::to_byte(wire::InstructionCode::FastBulkRead)));
  CHECK(bus::is_group_instruction(wire::Protocol::V2,
                                  wire::to_byte(wire::InstructionCode::SyncWrite)));
  CHECK_FALSE(
      bus::is_group_instruction(wire::Protocol::V2, wire::to_byte(wire::InstructionCode::Write)));
  CHECK_FALSE(
      bus::is_group_instruction(wire::Protocol::V2, wire::to_byte(wire::InstructionCode::Reboot)));
}

TEST_CASE("FEETECH group instructions are SYNC READ and SYNC WRITE only", "[bus][group][feetech]") {
  using wire::Protocol;
  CHECK(bus::is_group_instruction(Protocol::Feetech, 0x82));
  CHECK(bus::is_group_instruction(Protocol::Feetech, 0x83));
  // DYNAMIXEL's Fast Sync Read and Bulk Read/Write codes mean nothing in FEETECH.
  for (const std::uint8_t code : {0x8A, 0x92, 0x93, 0x9A, 0x03}) {
    CHECK_FALSE(bus::is_group_instruction(Protocol::Feetech, code));
  }
  CHECK(bus::is_group_instruction(Protocol::V1, 0x92));
}
