#include "model/spec/shared_fields.hpp"

#include <algorithm>
#include <string>

namespace dxlemu::model {
namespace {

wire::Protocol read_protocol(const JsonNode& n) {
  if (n.is_string()) {
    if (n.string() == wire::protocol_name(wire::Protocol::Feetech)) {
      return wire::Protocol::Feetech;
    }
    n.fail("unknown protocol \"" + n.string() + "\" (known: 1, 2, \"feetech\")");
  }
  return static_cast<wire::Protocol>(n.integer(1, 2));
}

}  // namespace

Family read_family(const JsonNode& family) {
  const std::string name = family.string();
  const auto f = family_from_name(name);
  if (!f) {
    family.fail("unknown family \"" + name + "\" (known: " + family_names() + ")");
  }
  return *f;
}

std::vector<wire::Protocol> read_protocols(const JsonNode& protocols, Family family) {
  std::vector<wire::Protocol> out;
  for (std::size_t i = 0, n = protocols.array_size(); i < n; ++i) {
    const wire::Protocol p = read_protocol(protocols.at(i));
    if (std::find(out.begin(), out.end(), p) != out.end()) {
      protocols.at(i).fail("lists a protocol twice");
    }
    out.push_back(p);
  }
  if (out.empty()) {
    protocols.fail("must list at least one protocol");
  }
  // A FEETECH family speaks FEETECH's protocol only, a ROBOTIS family DYNAMIXEL's only: the
  // family's rules (status bits, response levels) are one maker's.
  const Maker maker = traits_of(family).maker;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if ((out[i] == wire::Protocol::Feetech) != (maker == Maker::Feetech)) {
      protocols.at(i).fail("a model of the " + std::string(maker_name(maker)) + " family \"" +
                           std::string(family_name(family)) + "\" cannot speak " +
                           std::string(wire::protocol_title(out[i])));
    }
  }
  return out;
}

}  // namespace dxlemu::model
