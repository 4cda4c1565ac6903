#include "shipped_model.hpp"

#include <fstream>
#include <map>
#include <sstream>

#include "model/model_loader.hpp"

namespace dxlemu::test {

std::shared_ptr<const model::ModelSpec> shipped_model(const std::string& name) {
  // Tests ask for the same few models many times; parse each once.
  static std::map<std::string, std::shared_ptr<const model::ModelSpec>> cache;
  if (const auto it = cache.find(name); it != cache.end()) {
    return it->second;
  }
  const std::string path = std::string(DXLEMU_MODELS_DIR) + "/" + name + ".json";
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  auto spec = std::make_shared<const model::ModelSpec>(model::parse_model(text.str(), path));
  cache.emplace(name, spec);
  return spec;
}

}  // namespace dxlemu::test
