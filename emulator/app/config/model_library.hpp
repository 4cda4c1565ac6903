#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "model/spec/catalog_entry.hpp"
#include "model/spec/family_traits.hpp"
#include "model/spec/model_spec.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::app {

/// Which models `dxlemu models` lists: every condition that is set must hold.
struct ModelFilter {
  std::optional<model::Family> family;     ///< the model's behaviour family
  std::optional<wire::Protocol> protocol;  ///< one of the protocols the model can speak
  std::string name_fragment;  ///< in the name or the title, ignoring case; empty: any model

  /// True when `spec` meets every condition.
  bool matches(const model::ModelSpec& spec) const;
  /// True when the model of `entry` meets every condition: the catalog says all a filter asks,
  /// so filtering reads no model file.
  bool matches(const model::CatalogEntry& entry) const;
};

/// Every model the emulator can instantiate: the shipped models (models/catalog.json and the
/// catalogs of its maker folders) and the model files of any directories given with --models,
/// which may add models or replace a shipped one of the same name.
///
/// load() reads the catalogs and the user's files; a shipped model file is parsed the first time
/// a lookup needs the model, and kept (docs/model-format.md "The catalog"). So load() refuses a
/// bad catalog, a bad user's file and two models of one name or one number, naming the file, the
/// JSON pointer and the reason; a shipped file that cannot be parsed, or says otherwise than its
/// catalog entry, is refused by the lookup that first needs it, which throws model::ModelError
/// naming it (and again on every later lookup of it).
///
/// The lookups are const but fill the caches of parsed files and firmware variants: one mutex
/// serialises them, so a library shared between threads is no data race (the daemon has one
/// thread; a lookup costs a lock next to a file's parse, and a thread asking for a model being
/// parsed waits for that parse instead of repeating it).
class ModelLibrary {
 public:
  /// An empty library (load() makes a useful one).
  ModelLibrary();
  ~ModelLibrary();
  /// A moved-from library may only be assigned to or destroyed.
  ModelLibrary(ModelLibrary&& other) noexcept;
  ModelLibrary& operator=(ModelLibrary&& other) noexcept;
  ModelLibrary(const ModelLibrary&) = delete;
  ModelLibrary& operator=(const ModelLibrary&) = delete;

  /// Reads the shipped catalog in `shipped_dir` and those of its maker folders (each
  /// subdirectory with a catalog.json, e.g. feetech/), then parses every *.json file of each
  /// `extra_dirs` directory (catalog.json excepted). Parses no shipped model file. Throws
  /// model::ModelError for a bad catalog (or one naming a file that does not exist), a bad
  /// user's file or directory, two models that claim the same model number, and two catalog
  /// entries of the same name.
  static ModelLibrary load(const std::filesystem::path& shipped_dir,
                           const std::vector<std::filesystem::path>& extra_dirs);

  /// The model named `name` ("xm430-w350"), or with a firmware ("xl330-m288@52": the model running
  /// that firmware, model::model_for_firmware, built the first time it is asked for), or nullptr.
  /// Parses that model's file if no lookup did yet; throws model::ModelError when it cannot.
  std::shared_ptr<const model::ModelSpec> find(const std::string& name) const;
  /// Why find(`name`) found nothing, for an error message: an unknown model, or a firmware the
  /// model does not have (naming the ones it has: the model's file is parsed for them).
  std::string why_not_found(const std::string& name) const;
  /// The firmware variants of the model `name` ("xl330-m288@52"...), by version, highest first;
  /// empty for a model with one firmware. Parses the model's file and builds its variants.
  std::vector<std::shared_ptr<const model::ModelSpec>> variants_of(const std::string& name) const;
  /// The model of `maker` whose Model Number is `number` (of models sharing one, the one that
  /// declares no shares_model_number_with), or nullptr. Model numbers are unique per maker only.
  /// The catalog picks the model; only that model's file is parsed.
  std::shared_ptr<const model::ModelSpec> find(std::uint16_t number, model::Maker maker) const;
  /// Every model's name, in order; parses nothing.
  std::vector<std::string> names() const;
  /// All models, by name. Parses every model file not parsed yet (`dxlemu models`, the baud
  /// rates of `dxlemu clone`): a bad one throws model::ModelError.
  std::map<std::string, std::shared_ptr<const model::ModelSpec>> models() const;
  /// The models `filter` matches, by name. The catalog entries decide; only the files of the
  /// models matched are parsed.
  std::vector<std::shared_ptr<const model::ModelSpec>> select(const ModelFilter& filter) const;

 private:
  struct Entry;

  void add(std::unique_ptr<Entry> entry);
  void load_catalog(const std::filesystem::path& dir);
  /// The parsed model of `entry`, parsing its file if needed. Call with `*mutex_` locked.
  std::shared_ptr<const model::ModelSpec> spec_of(Entry& entry) const;
  /// The model of `entry` running firmware `version`, or nullptr. Call with `*mutex_` locked.
  std::shared_ptr<const model::ModelSpec> variant_of(Entry& entry, std::uint8_t version) const;

  /// By name. Fixed by load(); the parsed files and variants the entries keep are filled by
  /// lookups, under `mutex_`.
  std::map<std::string, std::unique_ptr<Entry>> entries_;
  /// Behind a pointer so that the library can be moved (load() returns it).
  std::unique_ptr<std::mutex> mutex_;
};

/// A directory of shipped data, the first of: $`env` when set and not empty; `bindir_relative`
/// from the running executable's directory (/proc/self/exe), the install layout's path, when
/// `marker` exists in it ("" : when it exists); else `source`, the source tree's copy this binary
/// was built from (a build-tree binary).
std::filesystem::path shipped_data_dir(const char* env,
                                       const std::filesystem::path& bindir_relative,
                                       const std::filesystem::path& marker,
                                       const std::filesystem::path& source);

/// The directory of the shipped models, the first of: $DXLEMU_MODELS_DIR when set and not empty;
/// the installed library, found from the running executable's directory (/proc/self/exe) by the
/// install layout's relative path (`../share/dxlemu/models` by default), when it holds a
/// catalog.json; else the source tree's models/ this binary was built from (a build-tree binary).
std::filesystem::path shipped_models_dir();

}  // namespace dxlemu::app
