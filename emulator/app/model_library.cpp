#include "app/model_library.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>

#include "model/model_error.hpp"
#include "model/model_loader.hpp"

namespace dxlemu::app {
namespace {

namespace fs = std::filesystem;

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw model::ModelError(path.string(), "", "cannot be read");
  }
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::shared_ptr<const model::ModelSpec> load_file(const fs::path& path) {
  return std::make_shared<const model::ModelSpec>(
      model::parse_model(read_file(path), path.string()));
}

}  // namespace

// A catalog.json of `dir`: its models, each file relative to `dir`.
void ModelLibrary::load_catalog(const fs::path& dir) {
  const fs::path catalog_path = dir / "catalog.json";
  nlohmann::json catalog;
  try {
    catalog = nlohmann::json::parse(read_file(catalog_path));
  } catch (const nlohmann::json::exception& e) {
    throw model::ModelError(catalog_path.string(), "", std::string("not valid JSON: ") + e.what());
  }
  const auto* entries = catalog.contains("models") ? &catalog["models"] : nullptr;
  if (entries == nullptr || !entries->is_array()) {
    throw model::ModelError(catalog_path.string(), "/models", "must be an array");
  }
  for (std::size_t i = 0; i < entries->size(); ++i) {
    const auto& entry = (*entries)[i];
    if (!entry.is_object() || !entry.contains("file") || !entry["file"].is_string()) {
      throw model::ModelError(catalog_path.string(), "/models/" + std::to_string(i) + "/file",
                              "must be a string");
    }
    const fs::path file = dir / entry["file"].get<std::string>();
    add(load_file(file), file.string());
  }
}

ModelLibrary ModelLibrary::load(const fs::path& shipped_dir,
                                const std::vector<fs::path>& extra_dirs) {
  ModelLibrary library;
  // DYNAMIXEL's catalog, then another maker's in each folder with its own (models/feetech/).
  library.load_catalog(shipped_dir);
  std::vector<fs::path> maker_dirs;
  for (const auto& f : fs::directory_iterator(shipped_dir)) {
    if (f.is_directory() && fs::is_regular_file(f.path() / "catalog.json")) {
      maker_dirs.push_back(f.path());
    }
  }
  std::sort(maker_dirs.begin(), maker_dirs.end());  // deterministic: directory order is not
  for (const fs::path& dir : maker_dirs) {
    library.load_catalog(dir);
  }
  for (const fs::path& dir : extra_dirs) {
    if (!fs::is_directory(dir)) {
      throw model::ModelError(dir.string(), "", "is not a directory");
    }
    std::vector<fs::path> files;
    for (const auto& f : fs::directory_iterator(dir)) {
      if (f.path().extension() == ".json" && f.path().filename() != "catalog.json") {
        files.push_back(f.path());
      }
    }
    std::sort(files.begin(), files.end());  // deterministic: directory order is not
    for (const fs::path& file : files) {
      auto spec = load_file(file);
      library.models_.erase(spec->name);  // a user's file replaces the shipped model of its name
      library.add(std::move(spec), file.string());
    }
  }
  for (const auto& [name, spec] : library.models_) {
    for (const model::FirmwareVariant& variant : spec->firmware_variants) {
      auto built = std::make_shared<const model::ModelSpec>(
          *model::model_for_firmware(*spec, variant.firmware_version, library.origins_[name]));
      std::string key = built->name;  // read before the pointer is moved into the map
      library.variants_.emplace(std::move(key), std::move(built));
    }
  }
  return library;
}

void ModelLibrary::add(std::shared_ptr<const model::ModelSpec> spec, const std::string& origin) {
  for (const auto& [name, other] : models_) {
    const bool declared =
        spec->shares_model_number_with == name || other->shares_model_number_with == spec->name;
    // Model numbers are one maker's: FEETECH's 777 says nothing of a DYNAMIXEL 777.
    if (other->model_number == spec->model_number && other->maker() == spec->maker() && !declared) {
      throw model::ModelError(origin, "/model_number",
                              "model number " + std::to_string(spec->model_number) +
                                  " is already used by " + name + " (" + origins_.at(name) +
                                  "); a model that reports another's number names it in "
                                  "shares_model_number_with");
    }
  }
  if (models_.count(spec->name) != 0) {
    throw model::ModelError(origin, "/name", "a model named " + spec->name + " is already loaded");
  }
  origins_[spec->name] = origin;
  models_.emplace(spec->name, std::move(spec));
}

std::shared_ptr<const model::ModelSpec> ModelLibrary::find(const std::string& name) const {
  if (const auto it = models_.find(name); it != models_.end()) {
    return it->second;
  }
  if (const auto it = variants_.find(name); it != variants_.end()) {
    return it->second;
  }
  // NAME@VERSION of the model's own (default) firmware is the model itself.
  const auto at = name.rfind('@');
  if (at == std::string::npos) {
    return nullptr;
  }
  const auto base = models_.find(name.substr(0, at));
  if (base != models_.end() &&
      std::to_string(base->second->firmware_version) == name.substr(at + 1)) {
    return base->second;
  }
  return nullptr;
}

std::string ModelLibrary::why_not_found(const std::string& name) const {
  const auto at = name.rfind('@');
  if (at != std::string::npos) {
    const auto base = models_.find(name.substr(0, at));
    if (base != models_.end()) {
      return base->first + " has no firmware \"" + name.substr(at + 1) +
             "\" (known: " + model::firmware_list(*base->second) + ")";
    }
  }
  return "unknown model \"" + name + "\" (dxlemu models lists them)";
}

std::vector<std::shared_ptr<const model::ModelSpec>> ModelLibrary::variants_of(
    const std::string& name) const {
  std::vector<std::shared_ptr<const model::ModelSpec>> out;
  const auto base = models_.find(name);
  if (base == models_.end()) {
    return out;
  }
  for (const model::FirmwareVariant& v : base->second->firmware_variants) {
    out.push_back(variants_.at(name + "@" + std::to_string(v.firmware_version)));
  }
  std::sort(out.begin(), out.end(),
            [](const auto& a, const auto& b) { return a->firmware_version > b->firmware_version; });
  return out;
}

std::shared_ptr<const model::ModelSpec> ModelLibrary::find(std::uint16_t number,
                                                           model::Maker maker) const {
  std::shared_ptr<const model::ModelSpec> sharing;
  for (const auto& [name, spec] : models_) {
    if (spec->model_number == number && spec->maker() == maker) {
      if (spec->shares_model_number_with.empty()) {
        return spec;
      }
      sharing = spec;
    }
  }
  return sharing;
}

std::vector<std::shared_ptr<const model::ModelSpec>> ModelLibrary::select(
    const ModelFilter& filter) const {
  std::vector<std::shared_ptr<const model::ModelSpec>> out;
  for (const auto& [name, spec] : models_) {
    if (filter.matches(*spec)) {
      out.push_back(spec);
    }
  }
  return out;
}

bool ModelFilter::matches(const model::ModelSpec& spec) const {
  if (family && spec.family != *family) {
    return false;
  }
  if (protocol &&
      std::find(spec.protocols.begin(), spec.protocols.end(), *protocol) == spec.protocols.end()) {
    return false;
  }
  const std::string fragment = lowercase(name_fragment);
  return lowercase(spec.name).find(fragment) != std::string::npos ||
         lowercase(spec.title).find(fragment) != std::string::npos;
}

fs::path shipped_data_dir(const char* env, const fs::path& bindir_relative, const fs::path& marker,
                          const fs::path& source) {
  if (const char* dir = std::getenv(env); dir != nullptr && *dir != '\0') {
    return dir;
  }
  // Why relative to the executable rather than an absolute path fixed at build time: the same
  // binary then works under any prefix (`cmake --install --prefix`, the .deb's /usr, a moved
  // tree). /proc/self/exe names the real file even when the binary is run through a symlink.
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    fs::path installed = (exe.parent_path() / bindir_relative).lexically_normal();
    if (fs::exists(marker.empty() ? installed : installed / marker, error)) {
      return installed;
    }
  }
  // No installed copy beside the binary: it runs from the build tree, next to its sources.
  return source;
}

fs::path shipped_models_dir() {
  return shipped_data_dir("DXLEMU_MODELS_DIR", DXLEMU_BINDIR_TO_MODELSDIR, "catalog.json",
                          DXLEMU_SOURCE_MODELS_DIR);
}

}  // namespace dxlemu::app
