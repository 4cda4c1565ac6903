#include "model/spec/catalog_entry.hpp"

#include <array>
#include <nlohmann/json.hpp>

#include "model/spec/json_node.hpp"
#include "model/spec/model_error.hpp"
#include "model/spec/shared_fields.hpp"

namespace dxlemu::model {
namespace {

using nlohmann::json;

constexpr std::array<std::string_view, 1> kCatalogFields = {"models"};
constexpr std::array<std::string_view, 7> kEntryFields = {
    "name", "title", "model_number", "shares_model_number_with", "family", "protocols", "file"};
constexpr std::int64_t kMaxModelNumber = 0xFFFF;

CatalogEntry read_entry(const JsonNode& n) {
  n.expect_object(kEntryFields);
  CatalogEntry entry;
  entry.pointer = n.pointer();
  entry.name = n.at("name").string();
  entry.title = n.at("title").string();
  entry.model_number = static_cast<std::uint16_t>(n.at("model_number").integer(0, kMaxModelNumber));
  if (n.has("shares_model_number_with")) {
    entry.shares_model_number_with = n.child("shares_model_number_with").string();
  }
  entry.family = read_family(n.at("family"));
  entry.protocols = read_protocols(n.at("protocols"), entry.family);
  entry.file = n.at("file").string();
  if (entry.name.empty()) {
    n.at("name").fail("must not be empty");
  }
  if (entry.file.empty()) {
    n.at("file").fail("must name the model file");
  }
  return entry;
}

// The protocols as a model file lists them: 2, 1 or "feetech".
std::string protocols_text(const std::vector<wire::Protocol>& protocols) {
  std::string out = "[";
  for (const wire::Protocol p : protocols) {
    out += out.size() == 1 ? "" : ", ";
    out += wire::protocol_json_text(p);
  }
  return out + "]";
}

std::string quoted(const std::string& text) {
  return text.empty() ? std::string("none") : "\"" + text + "\"";
}

}  // namespace

std::vector<CatalogEntry> parse_catalog(std::string_view json_text, const std::string& origin) {
  json document;
  try {
    document = json::parse(json_text);
  } catch (const json::exception& e) {
    throw ModelError(origin, "", std::string("not valid JSON: ") + e.what());
  }
  const JsonNode root(document, "", origin);
  root.expect_object(kCatalogFields);
  const JsonNode models = root.at("models");
  std::vector<CatalogEntry> entries;
  for (std::size_t i = 0, n = models.array_size(); i < n; ++i) {
    entries.push_back(read_entry(models.at(i)));
  }
  return entries;
}

CatalogEntry catalog_entry_of(const ModelSpec& spec) {
  return {spec.name,
          spec.title,
          spec.model_number,
          spec.shares_model_number_with,
          spec.family,
          spec.protocols,
          {},
          {}};
}

void check_against_catalog(const ModelSpec& spec, const std::string& origin,
                           const CatalogEntry& entry, const std::string& catalog) {
  const auto refuse = [&](const std::string& member, const std::string& file_says,
                          const std::string& catalog_says) {
    throw ModelError(origin, "/" + member,
                     "is " + file_says + ", but its entry in " + catalog + " (" + entry.pointer +
                         ") says " + catalog_says + "; the file and its entry must agree");
  };
  if (spec.name != entry.name) {
    refuse("name", quoted(spec.name), quoted(entry.name));
  }
  if (spec.title != entry.title) {
    refuse("title", quoted(spec.title), quoted(entry.title));
  }
  if (spec.model_number != entry.model_number) {
    refuse("model_number", std::to_string(spec.model_number), std::to_string(entry.model_number));
  }
  if (spec.shares_model_number_with != entry.shares_model_number_with) {
    refuse("shares_model_number_with", quoted(spec.shares_model_number_with),
           quoted(entry.shares_model_number_with));
  }
  if (spec.family != entry.family) {
    refuse("family", quoted(std::string(family_name(spec.family))),
           quoted(std::string(family_name(entry.family))));
  }
  if (spec.protocols != entry.protocols) {
    refuse("protocols", protocols_text(spec.protocols), protocols_text(entry.protocols));
  }
}

}  // namespace dxlemu::model
