#include "golden_file.hpp"
#include "text.hpp"

#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "wire/hex.hpp"

namespace dxlemu::test {
namespace {

void finish(std::vector<GoldenPacket>& out, std::optional<GoldenPacket>& current,
            const std::string& path) {
  if (!current) {
    return;
  }
  const GoldenPacket& p = *current;
  if (p.bytes.empty() || p.expect.empty() || p.source.empty() ||
      (p.kind != "instruction" && p.kind != "status" && p.kind != "fast_reply") ||
      (p.kind == "fast_reply") == p.lengths.empty()) {
    throw std::runtime_error(path + ": entry [" + p.name + "] is incomplete");
  }
  out.push_back(std::move(*current));
  current.reset();
}

}  // namespace

std::vector<GoldenPacket> load_golden_packets(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    throw std::runtime_error(path + ": cannot open");
  }
  std::vector<GoldenPacket> out;
  std::optional<GoldenPacket> current;
  std::set<std::string> names;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string where = path + ":" + std::to_string(line_no) + ": ";
    line = trim(line);
    if (line.empty() || line[0] == '#') {
      continue;
    }
    if (line.front() == '[' && line.back() == ']') {
      finish(out, current, path);
      current.emplace();
      current->name = line.substr(1, line.size() - 2);
      if (!names.insert(current->name).second) {
        throw std::runtime_error(where + "duplicate name " + current->name);
      }
      continue;
    }
    const auto colon = line.find(':');
    if (!current || colon == std::string::npos) {
      throw std::runtime_error(where + "expected [name] or key: value");
    }
    const std::string key = line.substr(0, colon);
    const std::string value = trim(line.substr(colon + 1));
    auto hex = [&](const std::string& text) {
      auto bytes = wire::parse_hex(text);
      if (!bytes) {
        throw std::runtime_error(where + "bad hex in " + key);
      }
      return *bytes;
    };
    if (key == "source") {
      current->source = value;
    } else if (key == "protocol") {
      if (value != "1" && value != "2") {
        throw std::runtime_error(where + "protocol must be 1 or 2");
      }
      current->protocol = value == "1" ? wire::Protocol::V1 : wire::Protocol::V2;
    } else if (key == "kind") {
      current->kind = value;
    } else if (key == "bytes") {
      current->bytes = hex(value);
    } else if (key == "printed") {
      current->printed = hex(value);
    } else if (key == "expect") {
      current->expect = value;
    } else if (key == "lengths") {
      std::istringstream ls(value);
      unsigned n = 0;
      while (ls >> n) {
        current->lengths.push_back(static_cast<std::uint16_t>(n));
      }
    } else if (key != "note") {
      throw std::runtime_error(where + "unknown key " + key);
    }
  }
  finish(out, current, path);
  return out;
}

std::vector<GoldenPacket> load_golden_packets() {
  return load_golden_packets(std::string(DXLEMU_TEST_DATA_DIR) + "/golden_packets.txt");
}

std::vector<GoldenPacket> load_golden_packets(wire::Protocol protocol) {
  std::vector<GoldenPacket> out;
  for (auto& p : load_golden_packets()) {
    if (p.protocol == protocol) {
      out.push_back(std::move(p));
    }
  }
  return out;
}

std::vector<std::uint8_t> concatenated(const std::vector<GoldenPacket>& packets) {
  std::vector<std::uint8_t> out;
  for (const auto& p : packets) {
    out.insert(out.end(), p.bytes.begin(), p.bytes.end());
  }
  return out;
}

}  // namespace dxlemu::test
