#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

namespace dxlemu::test {

/// One example frame of FEETECH's FT-SCS protocol page (reference/feetech/protocol-ft-scs.md,
/// Part 1), with what the page says it holds.
struct FeetechExample {
  std::string_view section;  ///< the page's section and example that print it first
  std::string_view kind;     ///< "instruction" or "status"
  std::vector<std::uint8_t> bytes;
  std::string_view expect;  ///< describe() of the decoded packet: the fields the page states
};

/// The 36 distinct frames printed on the page, in page order (a frame printed again, such as the
/// status FF FF 01 02 00 FC, is listed once, under the section that prints it first).
const std::vector<FeetechExample>& feetech_examples();

}  // namespace dxlemu::test
