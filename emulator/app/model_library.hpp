#pragma once

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "model/family_traits.hpp"
#include "model/model_spec.hpp"
#include "wire/protocol.hpp"

namespace dxlemu::app {

/// Which models `dxlemu models` lists: every condition that is set must hold.
struct ModelFilter {
  std::optional<model::Family> family;     ///< the model's behaviour family
  std::optional<wire::Protocol> protocol;  ///< one of the protocols the model can speak
  std::string name_fragment;  ///< in the name or the title, ignoring case; empty: any model

  /// True when `spec` meets every condition.
  bool matches(const model::ModelSpec& spec) const;
};

/// Every model the emulator can instantiate: the shipped models (models/catalog.json) and the
/// model files of any directories given with --models, which may add models or replace a shipped
/// one of the same name. Loading is all or nothing: a bad file throws model::ModelError naming it.
class ModelLibrary {
 public:
  /// Loads the shipped catalog in `shipped_dir` and those of its maker folders (each subdirectory
  /// with a catalog.json, e.g. feetech/), then every *.json file of each `extra_dirs`
  /// directory (catalog.json excepted). Throws model::ModelError for a bad file or directory, and
  /// for two models that claim the same model number.
  static ModelLibrary load(const std::filesystem::path& shipped_dir,
                           const std::vector<std::filesystem::path>& extra_dirs);

  /// The model named `name` ("xm430-w350"), or with a firmware ("xl330-m288@52": the model running
  /// that firmware, model::model_for_firmware), or nullptr.
  std::shared_ptr<const model::ModelSpec> find(const std::string& name) const;
  /// Why find(`name`) found nothing, for an error message: an unknown model, or a firmware the
  /// model does not have (naming the ones it has).
  std::string why_not_found(const std::string& name) const;
  /// The firmware variants of the model `name` ("xl330-m288@52"...), by version, highest first;
  /// empty for a model with one firmware.
  std::vector<std::shared_ptr<const model::ModelSpec>> variants_of(const std::string& name) const;
  /// The model of `maker` whose Model Number is `number` (of models sharing one, the one that
  /// declares no shares_model_number_with), or nullptr. Model numbers are unique per maker only.
  std::shared_ptr<const model::ModelSpec> find(std::uint16_t number, model::Maker maker) const;
  /// All models, by name.
  const std::map<std::string, std::shared_ptr<const model::ModelSpec>>& models() const {
    return models_;
  }
  /// The models `filter` matches, by name.
  std::vector<std::shared_ptr<const model::ModelSpec>> select(const ModelFilter& filter) const;

 private:
  void add(std::shared_ptr<const model::ModelSpec> spec, const std::string& origin);
  void load_catalog(const std::filesystem::path& dir);

  std::map<std::string, std::shared_ptr<const model::ModelSpec>> models_;
  std::map<std::string, std::string> origins_;
  /// "NAME@VERSION" -> the model running that firmware: built once, after every file is read (a
  /// user's file may replace a shipped model and its variants with it).
  std::map<std::string, std::shared_ptr<const model::ModelSpec>> variants_;
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
