// The model library (docs/model-format.md "The catalog"): a start reads the catalogs and the
// user's files, and a shipped model file is parsed when a lookup first needs it. Each test builds
// a library over a copy of a few shipped files in a temporary directory, breaking the files a
// lookup must not read: a start that parsed them would be refused.
#include <stdlib.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "app/config/model_library.hpp"
#include "app/config/robot_library.hpp"
#include "model/spec/model_error.hpp"
#include "temp_dir.hpp"

using namespace dxlemu;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A file no JSON parser accepts: a lookup that reads it throws.
constexpr const char* kBroken = "{ \"name\": ";

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void write(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// A directory of model files for one test.
struct TempDir : test::TempDir {
  TempDir() : test::TempDir("dxlemu-library") {}
};

// The shipped catalog entry of `name` (models/catalog.json).
json shipped_entry(const std::string& name) {
  const json catalog = json::parse(slurp(fs::path(DXLEMU_MODELS_DIR) / "catalog.json"));
  for (const json& entry : catalog["models"]) {
    if (entry["name"] == name) {
      return entry;
    }
  }
  FAIL("no catalog entry " << name);
  return {};
}

// A shipped library of the models `names` in `dir`: their catalog entries and copies of their
// files.
void copy_models(const fs::path& dir, const std::vector<std::string>& names) {
  json catalog = {{"models", json::array()}};
  for (const std::string& name : names) {
    catalog["models"].push_back(shipped_entry(name));
    fs::copy_file(fs::path(DXLEMU_MODELS_DIR) / (name + ".json"), dir / (name + ".json"));
  }
  write(dir / "catalog.json", catalog.dump(2));
}

// The message of the model::ModelError `lookup` throws, or "no refusal".
template <class Lookup>
std::string lookup_refusal(Lookup lookup) {
  try {
    lookup();
  } catch (const model::ModelError& e) {
    return e.what();
  }
  return "no refusal";
}

}  // namespace

TEST_CASE("A start parses no shipped model file, and a lookup parses only the model it needs",
          "[app][library]") {
  TempDir dir;
  copy_models(dir.path(), {"ax-12a", "xl330-m288", "xm430-w350"});
  write(dir.path() / "ax-12a.json", kBroken);
  const fs::path broken = dir.path() / "ax-12a.json";
  const auto library = app::ModelLibrary::load(dir.path(), {});
  CHECK(library.names() == std::vector<std::string>{"ax-12a", "xl330-m288", "xm430-w350"});
  const auto spec = library.find("xm430-w350");
  REQUIRE(spec != nullptr);
  CHECK(spec->model_number == 1020);
  CHECK(library.find("xm430-w350") == spec);  // parsed once, then kept
  CHECK(library.find(1020, model::Maker::Robotis) == spec);
  CHECK(library.find("no-such-model") == nullptr);
  CHECK(library.why_not_found("no-such-model") ==
        "unknown model \"no-such-model\" (dxlemu models lists them)");
  // The catalog decides what a filter matches: the broken AX-12A is not read for an X filter.
  app::ModelFilter x_family;
  x_family.family = model::Family::X;
  CHECK(library.select(x_family).size() == 2);
  // The broken file is refused naming it when a lookup first needs it, and on every later one.
  const std::string message = broken.string() + ": /: not valid JSON: ";
  CHECK_THAT(lookup_refusal([&] { library.find("ax-12a"); }), Catch::StartsWith(message));
  CHECK_THAT(lookup_refusal([&] { library.find("ax-12a"); }), Catch::StartsWith(message));
  CHECK_THAT(lookup_refusal([&] { library.find(12, model::Maker::Robotis); }),
             Catch::StartsWith(message));
  CHECK_THAT(lookup_refusal([&] { library.models(); }), Catch::StartsWith(message));
  CHECK(library.find("xm430-w350") == spec);
}

TEST_CASE("Firmware variants are built when first asked for, and kept", "[app][library]") {
  TempDir dir;
  copy_models(dir.path(), {"xl330-m288", "xm430-w350"});
  write(dir.path() / "xm430-w350.json", kBroken);
  const auto library = app::ModelLibrary::load(dir.path(), {});
  const auto variant = library.find("xl330-m288@52");
  REQUIRE(variant != nullptr);
  CHECK(variant->name == "xl330-m288@52");
  CHECK(variant->firmware_version == 52);
  CHECK(library.find("xl330-m288@52") == variant);
  CHECK(library.variants_of("xl330-m288") == std::vector{variant});
  CHECK(library.find("xl330-m288@53") == library.find("xl330-m288"));
  CHECK(library.find("xl330-m288@052") == nullptr);
  CHECK(library.why_not_found("xl330-m288@51") ==
        "xl330-m288 has no firmware \"51\" (known: 53, 52)");
  // NAME@FIRMWARE needs the model's file: a broken one is refused, naming it.
  CHECK_THAT(lookup_refusal([&] { library.find("xm430-w350@45"); }),
             Catch::StartsWith((dir.path() / "xm430-w350.json").string() + ": /: not valid JSON"));
}

TEST_CASE("A shipped file that says otherwise than its catalog entry is refused naming the member",
          "[app][library]") {
  using Case = std::pair<std::string, json>;
  const std::vector<Case> cases = {
      {"name", "xm430-w351"}, {"title", "XM430-W351"},
      {"model_number", 1021}, {"shares_model_number_with", "xm430-w210"},
      {"family", "mx2"},      {"protocols", {1, 2}},
  };
  for (const auto& [member, value] : cases) {
    INFO(member);
    TempDir dir;
    copy_models(dir.path(), {"xm430-w350"});
    const fs::path file = dir.path() / "xm430-w350.json";
    json model = json::parse(slurp(file));
    model[member] = value;
    write(file, model.dump(2));
    const auto library = app::ModelLibrary::load(dir.path(), {});
    const std::string catalog = (dir.path() / "catalog.json").string();
    CHECK_THAT(lookup_refusal([&] { library.find("xm430-w350"); }),
               Catch::StartsWith(file.string() + ": /" + member + ": is ") &&
                   Catch::Contains(", but its entry in " + catalog + " (/models/0) says ") &&
                   Catch::EndsWith("; the file and its entry must agree"));
  }
  TempDir dir;
  copy_models(dir.path(), {"xm430-w350"});
  json model = json::parse(slurp(dir.path() / "xm430-w350.json"));
  model["model_number"] = 1021;
  write(dir.path() / "xm430-w350.json", model.dump(2));
  CHECK(lookup_refusal([&] { app::ModelLibrary::load(dir.path(), {}).find("xm430-w350"); }) ==
        (dir.path() / "xm430-w350.json").string() + ": /model_number: is 1021, but its entry in " +
            (dir.path() / "catalog.json").string() +
            " (/models/0) says 1020; the file and its entry must agree");
}

TEST_CASE("A start refuses a bad catalog naming the file, the JSON pointer and the reason",
          "[app][library]") {
  const json ax = shipped_entry("ax-12a");
  const json xm = shipped_entry("xm430-w350");
  json again = xm;  // XM430-W350 listed twice (with another number: that is checked first)
  again["model_number"] = 1021;
  json twin = xm;  // another model claiming XM430-W350's number
  twin["name"] = "xm430-twin";
  json unknown_member = xm;
  unknown_member["firmware"] = 45;
  json unknown_family = xm;
  unknown_family["family"] = "q";
  json feetech_protocol = xm;
  feetech_protocol["protocols"] = {"feetech"};
  json no_file = xm;
  no_file["file"] = "missing.json";
  json no_title = xm;
  no_title.erase("title");
  using Case = std::pair<std::string, std::string>;
  const std::vector<Case> cases = {
      {"{", "/: not valid JSON: "},
      {R"({"model": []})", "/model: unknown field"},
      {R"({})", "/: missing required field \"models\""},
      {R"({"models": {}})", "/models: must be an array"},
      {json{{"models", {ax, 12}}}.dump(), "/models/1: must be an object"},
      {json{{"models", {no_title}}}.dump(), "/models/0: missing required field \"title\""},
      {json{{"models", {unknown_member}}}.dump(), "/models/0/firmware: unknown field"},
      {json{{"models", {unknown_family}}}.dump(), "/models/0/family: unknown family \"q\""},
      {json{{"models", {feetech_protocol}}}.dump(),
       "/models/0/protocols/0: a model of the ROBOTIS family \"x\" cannot speak FEETECH"},
      {json{{"models", {no_file}}}.dump(), "/models/0/file: names "},
      {json{{"models", {ax, xm, again}}}.dump(),
       "/models/2/name: a model named xm430-w350 is already loaded"},
      {json{{"models", {xm, twin}}}.dump(),
       "/models/1/model_number: model number 1020 is already used by xm430-w350 ("},
  };
  for (const auto& [catalog, message] : cases) {
    INFO(catalog);
    TempDir dir;
    // Every model file is broken: what the start refuses it finds in the catalog alone.
    write(dir.path() / "ax-12a.json", kBroken);
    write(dir.path() / "xm430-w350.json", kBroken);
    write(dir.path() / "catalog.json", catalog);
    CHECK_THAT(lookup_refusal([&] { app::ModelLibrary::load(dir.path(), {}); }),
               Catch::StartsWith((dir.path() / "catalog.json").string() + ": " + message));
  }
}

TEST_CASE("Catalog entries that name each other share a model number, as their files do",
          "[app][library]") {
  TempDir dir;
  copy_models(dir.path(), {"xc430-t150bb", "xc430-w150"});
  const auto library = app::ModelLibrary::load(dir.path(), {});
  // Of two models sharing a number, the one that declares no sharing answers to it.
  CHECK(library.find(1070, model::Maker::Robotis) == library.find("xc430-w150"));
  CHECK(library.find("xc430-t150bb")->shares_model_number_with == "xc430-w150");
}

TEST_CASE("A maker folder's catalog is read at start, and a name in two catalogs is refused",
          "[app][library][feetech]") {
  TempDir dir;
  copy_models(dir.path(), {"xm430-w350"});
  fs::create_directory(dir.path() / "feetech");
  json catalog = {{"models", {shipped_entry("xm430-w350")}}};
  catalog["models"][0]["model_number"] = 1;
  write(dir.path() / "feetech" / "catalog.json", catalog.dump());
  write(dir.path() / "feetech" / "xm430-w350.json", kBroken);
  CHECK_THAT(lookup_refusal([&] { app::ModelLibrary::load(dir.path(), {}); }),
             Catch::StartsWith((dir.path() / "feetech" / "catalog.json").string() +
                               ": /models/0/name: a model named xm430-w350 is already loaded (" +
                               (dir.path() / "xm430-w350.json").string() + ")"));
}

TEST_CASE("The user's model files are parsed at start and replace the shipped model of their name",
          "[app][library]") {
  TempDir shipped;
  copy_models(shipped.path(), {"xl330-m288", "xm430-w350"});
  write(shipped.path() / "xl330-m288.json", kBroken);  // replaced: never read
  TempDir user;
  json model = json::parse(slurp(fs::path(DXLEMU_MODELS_DIR) / "xl330-m288.json"));
  model["title"] = "XL330-M288 (mine)";
  write(user.path() / "xl330-m288.json", model.dump(2));
  const auto library = app::ModelLibrary::load(shipped.path(), {user.path()});
  CHECK(library.find("xl330-m288")->title == "XL330-M288 (mine)");
  CHECK(library.find("xl330-m288@52")->title == "XL330-M288 (mine)");
  CHECK(library.find(1200, model::Maker::Robotis)->title == "XL330-M288 (mine)");

  // A user's file is refused at start, used or not.
  write(user.path() / "broken.json", kBroken);
  CHECK_THAT(lookup_refusal([&] { app::ModelLibrary::load(shipped.path(), {user.path()}); }),
             Catch::StartsWith((user.path() / "broken.json").string() + ": /: not valid JSON"));
  fs::remove(user.path() / "broken.json");
  // As is one claiming a shipped model's number, which the shipped entry says.
  model["name"] = "my-servo";
  model["model_number"] = 1020;
  write(user.path() / "my-servo.json", model.dump(2));
  CHECK(lookup_refusal([&] { app::ModelLibrary::load(shipped.path(), {user.path()}); }) ==
        (user.path() / "my-servo.json").string() +
            ": /model_number: model number 1020 is already used by xm430-w350 (" +
            (shipped.path() / "xm430-w350.json").string() +
            "); a model that reports another's number names it in shares_model_number_with");
}

TEST_CASE("The robot profiles parse only the models their servos use", "[app][library][robots]") {
  // A copy of the shipped library in which every model no profile names is broken.
  std::set<std::string> used;
  for (const auto& f : fs::directory_iterator(DXLEMU_ROBOTS_DIR)) {
    if (f.path().extension() == ".json") {
      const json profile = json::parse(slurp(f.path()));
      for (const json& port : profile["ports"]) {
        for (const json& servo : port["servos"]) {
          used.insert(servo["model"].get<std::string>());
        }
      }
    }
  }
  REQUIRE(used.count("sts3215") == 1);
  TempDir dir;
  fs::copy(DXLEMU_MODELS_DIR, dir.path(), fs::copy_options::recursive);
  std::size_t broken = 0;
  for (const auto& f : fs::recursive_directory_iterator(dir.path())) {
    const fs::path& path = f.path();
    if (path.extension() == ".json" && path.filename() != "catalog.json" &&
        path.parent_path().filename() != "schema" && used.count(path.stem().string()) == 0) {
      write(path, kBroken);
      ++broken;
    }
  }
  CHECK(broken > used.size());
  const auto library = app::ModelLibrary::load(dir.path(), {});
  const auto robots = app::RobotLibrary::load(DXLEMU_ROBOTS_DIR, {}, library);
  CHECK(robots.find("so101-follower") != nullptr);
  CHECK(library.find("sts3215") != nullptr);
  CHECK_THROWS_AS(library.find("ax-12a"), model::ModelError);
}

TEST_CASE("Threads sharing a library get the one parsed model", "[app][library]") {
  const auto library = app::ModelLibrary::load(DXLEMU_MODELS_DIR, {});
  constexpr int kThreads = 4;
  std::vector<std::shared_ptr<const model::ModelSpec>> found(kThreads);
  std::vector<std::shared_ptr<const model::ModelSpec>> variants(kThreads);
  {
    std::vector<std::jthread> threads;
    threads.reserve(kThreads);
    for (int i = 0; i < kThreads; ++i) {
      threads.emplace_back([&, i] {
        found[i] = library.find("xl330-m288");
        variants[i] = library.find("xl330-m288@52");
      });
    }
  }
  for (int i = 0; i < kThreads; ++i) {
    REQUIRE(found[i] != nullptr);
    CHECK(found[i] == found[0]);
    CHECK(variants[i] == variants[0]);
  }
}
