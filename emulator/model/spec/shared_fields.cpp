#include "model/spec/shared_fields.hpp"

#include <algorithm>
#include <string>

namespace dxlemu::model {
namespace {

wire::Protocol read_protocol(const JsonNode& n) {
  // A protocol with a number is written as that number, the others by their spelling.
  if (n.is_string()) {
    const auto p = wire::protocol_from_spelling(n.string());
    if (!p || wire::protocol_number(*p) != 0) {
      n.fail("unknown protocol \"" + n.string() + "\" (known: " + wire::protocol_json_list() + ")");
    }
    return *p;
  }
  const auto p = wire::protocol_from_number(
      n.integer(wire::lowest_protocol_number(), wire::highest_protocol_number()));
  if (!p) {
    n.fail("no protocol has this number (known: " + wire::protocol_json_list() + ")");
  }
  return *p;
}

// The protocols of an array: each known, none twice, at least one.
std::vector<wire::Protocol> read_protocol_list(const JsonNode& list) {
  std::vector<wire::Protocol> out;
  for (std::size_t i = 0, n = list.array_size(); i < n; ++i) {
    const wire::Protocol p = read_protocol(list.at(i));
    if (std::find(out.begin(), out.end(), p) != out.end()) {
      list.at(i).fail("lists a protocol twice");
    }
    out.push_back(p);
  }
  if (out.empty()) {
    list.fail("must list at least one protocol");
  }
  return out;
}

// `1, 2, "modbus"`: protocols as JSON writes them, for messages.
std::string protocols_json_text(const std::vector<wire::Protocol>& protocols) {
  std::string out;
  for (const wire::Protocol p : protocols) {
    if (!out.empty()) {
      out += ", ";
    }
    out += wire::protocol_json_text(p);
  }
  return out;
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
  std::vector<wire::Protocol> out = read_protocol_list(protocols);
  // A FEETECH family speaks FEETECH's protocol only, a ROBOTIS family DYNAMIXEL's only: the
  // family's rules (status bits, response levels) are one maker's.
  const Maker maker = traits_of(family).maker;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (wire::traits(out[i]).maker != maker_name(maker)) {
      protocols.at(i).fail("a model of the " + std::string(maker_name(maker)) + " family \"" +
                           std::string(family_name(family)) + "\" cannot speak " +
                           std::string(wire::protocol_title(out[i])));
    }
  }
  return out;
}

std::vector<wire::Protocol> read_absent_in(const JsonNode& absent_in,
                                           const std::vector<wire::Protocol>& model_protocols) {
  std::vector<wire::Protocol> out = read_protocol_list(absent_in);
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (std::find(model_protocols.begin(), model_protocols.end(), out[i]) ==
        model_protocols.end()) {
      absent_in.at(i).fail("names " + wire::protocol_json_text(out[i]) +
                           ", which the model does not speak (its protocols: " +
                           protocols_json_text(model_protocols) + ")");
    }
  }
  // Every listed one is the model's and none is listed twice: equal sizes mean all of them.
  if (out.size() == model_protocols.size()) {
    absent_in.fail(
        "names every protocol the model speaks: an item none of them reaches is no item");
  }
  return out;
}

}  // namespace dxlemu::model
