#include "app/config/model_library.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <system_error>

#include "model/spec/firmware_variant.hpp"
#include "model/spec/model_error.hpp"
#include "model/spec/model_loader.hpp"

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

// One model of the library: what its catalog entry (or, for a user's file, the file) says, and
// once a lookup needed them, its parsed file and the firmware variants built from it.
struct ModelLibrary::Entry {
  model::CatalogEntry facts;
  fs::path file;
  /// The catalog that lists the model; empty for a user's file, which load() parses.
  std::string catalog;
  /// Null until the file is parsed. Guarded by ModelLibrary::mutex_, as `variants`.
  std::shared_ptr<const model::ModelSpec> spec;
  std::map<std::uint8_t, std::shared_ptr<const model::ModelSpec>> variants;

  /// The file that states the entry's facts, for messages: the catalog, else the model file.
  std::string origin() const { return catalog.empty() ? file.string() : catalog; }
};

ModelLibrary::ModelLibrary() : mutex_(std::make_unique<std::mutex>()) {}
ModelLibrary::~ModelLibrary() = default;
ModelLibrary::ModelLibrary(ModelLibrary&& other) noexcept = default;
ModelLibrary& ModelLibrary::operator=(ModelLibrary&& other) noexcept = default;

// A catalog.json of `dir`: its models, each file relative to `dir`. The files are only checked
// to exist (a stat each: a catalog naming a missing file is refused at start, with its entry).
void ModelLibrary::load_catalog(const fs::path& dir) {
  const fs::path catalog_path = dir / "catalog.json";
  for (model::CatalogEntry& facts :
       model::parse_catalog(read_file(catalog_path), catalog_path.string())) {
    fs::path file = dir / facts.file;
    std::error_code error;
    if (!fs::is_regular_file(file, error)) {
      throw model::ModelError(catalog_path.string(), facts.pointer + "/file",
                              "names " + file.string() + ", which is not a file");
    }
    auto entry = std::make_unique<Entry>();
    entry->facts = std::move(facts);
    entry->file = std::move(file);
    entry->catalog = catalog_path.string();
    add(std::move(entry));
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
  // The user's files are parsed now: they are few, and a mistake in one is best refused at
  // once, whether or not this run uses that model.
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
      auto entry = std::make_unique<Entry>();
      entry->spec = load_file(file);
      entry->facts = model::catalog_entry_of(*entry->spec);
      entry->file = file;
      // A user's file replaces the shipped model of its name, and with it its variants.
      library.entries_.erase(entry->facts.name);
      library.add(std::move(entry));
    }
  }
  return library;
}

void ModelLibrary::add(std::unique_ptr<Entry> entry) {
  const model::CatalogEntry& facts = entry->facts;
  for (const auto& [name, other] : entries_) {
    const bool declared = facts.shares_model_number_with == name ||
                          other->facts.shares_model_number_with == facts.name;
    // Model numbers are one maker's: FEETECH's 777 says nothing of a DYNAMIXEL 777.
    if (other->facts.model_number == facts.model_number && other->facts.maker() == facts.maker() &&
        !declared) {
      throw model::ModelError(entry->origin(), facts.pointer + "/model_number",
                              "model number " + std::to_string(facts.model_number) +
                                  " is already used by " + name + " (" + other->file.string() +
                                  "); a model that reports another's number names it in "
                                  "shares_model_number_with");
    }
  }
  if (entries_.count(facts.name) != 0) {
    throw model::ModelError(entry->origin(), facts.pointer + "/name",
                            "a model named " + facts.name + " is already loaded (" +
                                entries_.at(facts.name)->file.string() + ")");
  }
  std::string name = facts.name;  // read before the entry is moved into the map
  entries_.emplace(std::move(name), std::move(entry));
}

std::shared_ptr<const model::ModelSpec> ModelLibrary::spec_of(Entry& entry) const {
  if (!entry.spec) {
    // Not kept on failure: every later lookup of the model reads the file again and throws the
    // same refusal, so no caller meets a half-made model.
    auto spec = load_file(entry.file);
    model::check_against_catalog(*spec, entry.file.string(), entry.facts, entry.catalog);
    entry.spec = std::move(spec);
  }
  return entry.spec;
}

std::shared_ptr<const model::ModelSpec> ModelLibrary::variant_of(Entry& entry,
                                                                 std::uint8_t version) const {
  auto base = spec_of(entry);
  if (version == base->firmware_version) {
    return base;  // NAME@VERSION of the model's own (default) firmware is the model itself
  }
  if (const auto it = entry.variants.find(version); it != entry.variants.end()) {
    return it->second;
  }
  auto built = model::model_for_firmware(*base, version, entry.file.string());
  if (!built) {
    return nullptr;
  }
  auto variant = std::make_shared<const model::ModelSpec>(std::move(*built));
  entry.variants.emplace(version, variant);
  return variant;
}

std::shared_ptr<const model::ModelSpec> ModelLibrary::find(const std::string& name) const {
  const std::lock_guard lock(*mutex_);
  if (const auto it = entries_.find(name); it != entries_.end()) {
    return spec_of(*it->second);
  }
  const auto at = name.rfind('@');
  if (at == std::string::npos) {
    return nullptr;
  }
  const auto base = entries_.find(name.substr(0, at));
  if (base == entries_.end()) {
    return nullptr;
  }
  // The firmware as the variant's name spells it ("52", not "052").
  const std::string firmware = name.substr(at + 1);
  auto spec = spec_of(*base->second);
  if (std::to_string(spec->firmware_version) == firmware) {
    return spec;
  }
  for (const model::FirmwareVariant& v : spec->firmware_variants) {
    if (std::to_string(v.firmware_version) == firmware) {
      return variant_of(*base->second, v.firmware_version);
    }
  }
  return nullptr;
}

std::string ModelLibrary::why_not_found(const std::string& name) const {
  const auto at = name.rfind('@');
  if (at != std::string::npos) {
    const std::lock_guard lock(*mutex_);
    const auto base = entries_.find(name.substr(0, at));
    if (base != entries_.end()) {
      return base->first + " has no firmware \"" + name.substr(at + 1) +
             "\" (known: " + model::firmware_list(*spec_of(*base->second)) + ")";
    }
  }
  return "unknown model \"" + name + "\" (dxlemu models lists them)";
}

std::vector<std::shared_ptr<const model::ModelSpec>> ModelLibrary::variants_of(
    const std::string& name) const {
  std::vector<std::shared_ptr<const model::ModelSpec>> out;
  const std::lock_guard lock(*mutex_);
  const auto base = entries_.find(name);
  if (base == entries_.end()) {
    return out;
  }
  for (const model::FirmwareVariant& v : spec_of(*base->second)->firmware_variants) {
    out.push_back(variant_of(*base->second, v.firmware_version));
  }
  std::sort(out.begin(), out.end(),
            [](const auto& a, const auto& b) { return a->firmware_version > b->firmware_version; });
  return out;
}

std::shared_ptr<const model::ModelSpec> ModelLibrary::find(std::uint16_t number,
                                                           model::Maker maker) const {
  const std::lock_guard lock(*mutex_);
  Entry* sharing = nullptr;
  for (const auto& [name, entry] : entries_) {
    if (entry->facts.model_number == number && entry->facts.maker() == maker) {
      if (entry->facts.shares_model_number_with.empty()) {
        return spec_of(*entry);
      }
      sharing = entry.get();
    }
  }
  return sharing != nullptr ? spec_of(*sharing) : nullptr;
}

std::vector<std::string> ModelLibrary::names() const {
  std::vector<std::string> out;
  out.reserve(entries_.size());
  for (const auto& [name, entry] : entries_) {
    out.push_back(name);
  }
  return out;
}

std::map<std::string, std::shared_ptr<const model::ModelSpec>> ModelLibrary::models() const {
  std::map<std::string, std::shared_ptr<const model::ModelSpec>> out;
  const std::lock_guard lock(*mutex_);
  for (const auto& [name, entry] : entries_) {
    out.emplace(name, spec_of(*entry));
  }
  return out;
}

std::vector<std::shared_ptr<const model::ModelSpec>> ModelLibrary::select(
    const ModelFilter& filter) const {
  std::vector<std::shared_ptr<const model::ModelSpec>> out;
  const std::lock_guard lock(*mutex_);
  for (const auto& [name, entry] : entries_) {
    if (filter.matches(entry->facts)) {
      out.push_back(spec_of(*entry));
    }
  }
  return out;
}

bool ModelFilter::matches(const model::ModelSpec& spec) const {
  return matches(model::catalog_entry_of(spec));
}

bool ModelFilter::matches(const model::CatalogEntry& entry) const {
  if (family && entry.family != *family) {
    return false;
  }
  if (protocol && std::find(entry.protocols.begin(), entry.protocols.end(), *protocol) ==
                      entry.protocols.end()) {
    return false;
  }
  const std::string fragment = lowercase(name_fragment);
  return lowercase(entry.name).find(fragment) != std::string::npos ||
         lowercase(entry.title).find(fragment) != std::string::npos;
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
