#include "shipped_model.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "model/spec/model_loader.hpp"

namespace dxlemu::test {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

std::shared_ptr<const model::ModelSpec> shipped_model(const std::string& name) {
  // Tests ask for the same few models many times; parse each once.
  static std::map<std::string, std::shared_ptr<const model::ModelSpec>> cache;
  if (const auto it = cache.find(name); it != cache.end()) {
    return it->second;
  }
  const std::string path = std::string(DXLEMU_MODELS_DIR) + "/" + name + ".json";
  auto spec = std::make_shared<const model::ModelSpec>(model::parse_model(slurp(path), path));
  cache.emplace(name, spec);
  return spec;
}

std::vector<std::shared_ptr<const model::ModelSpec>> catalog_models() {
  const nlohmann::json catalog =
      nlohmann::json::parse(slurp(std::string(DXLEMU_MODELS_DIR) + "/catalog.json"));
  std::vector<std::shared_ptr<const model::ModelSpec>> out;
  for (const auto& entry : catalog.at("models")) {
    out.push_back(
        shipped_model(std::filesystem::path(entry.at("file").get<std::string>()).stem().string()));
  }
  return out;
}

}  // namespace dxlemu::test
