// The model files in models/ load, agree with the catalog, and match the ROBOTIS reference pages
// row by row (address, size, access, area, initial value, printed range) of ../shared/reference
// beside the checkout (the tests fail without it).
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <stdexcept>

#include "model/spec/model_loader.hpp"
#include "model/table/control_table.hpp"
#include "reference_page.hpp"
#include "shipped_model.hpp"

using namespace dxlemu;
namespace fs = std::filesystem;

namespace {

const fs::path kModels(DXLEMU_MODELS_DIR);

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The catalog's entries, by value: a range-for over a member of a temporary would dangle.
nlohmann::json catalog_entries() {
  return nlohmann::json::parse(slurp(kModels / "catalog.json")).at("models");
}

// Item notes of a model file by key. A model may differ from the printed table only where the
// item's note says why, starting with the field ("range: ...", "initial: ...", "access: ...").
std::map<std::string, std::string> item_notes(const std::string& name) {
  const nlohmann::json file = nlohmann::json::parse(slurp(kModels / (name + ".json")));
  std::map<std::string, std::string> notes;
  for (const auto& item : file.at("items")) {
    if (item.contains("note")) {
      notes[item.at("key").get<std::string>()] = item.at("note").get<std::string>();
    }
  }
  return notes;
}

bool documented(const std::map<std::string, std::string>& notes, const std::string& key,
                const std::string& field) {
  const auto it = notes.find(key);
  return it != notes.end() && it->second.find(field + ":") != std::string::npos;
}

// "Indirect Address 12" -> "Indirect Address": the series a page may elide with "…".
std::string series_of(const std::string& name) {
  const auto space = name.find_last_of(' ');
  if (space == std::string::npos ||
      name.find_first_not_of("0123456789", space + 1) != std::string::npos) {
    return name;
  }
  return name.substr(0, space);
}

std::int64_t read_back(model::ControlTable& table, const model::ItemSpec& item) {
  std::vector<std::uint8_t> bytes;
  REQUIRE(table.bus_read(item.address, item.size, bytes).ok());
  std::uint64_t raw = 0;
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    raw |= std::uint64_t{bytes[i]} << (8 * i);
  }
  if (item.is_signed && (raw >> (8 * item.size - 1)) != 0) {
    return static_cast<std::int64_t>(raw) - (std::int64_t{1} << (8 * item.size));
  }
  return static_cast<std::int64_t>(raw);
}

}  // namespace

TEST_CASE("The catalog lists a model for every reference page and every one loads",
          "[model][shipped]") {
  std::set<std::string> listed;
  const nlohmann::json entries = catalog_entries();
  for (const auto& entry : entries) {
    listed.insert(entry["file"].get<std::string>());
  }
  std::set<std::string> present;
  for (const auto& f : fs::directory_iterator(kModels)) {
    if (f.path().extension() == ".json" && f.path().filename() != "catalog.json") {
      present.insert(f.path().filename().string());
    }
  }
  CHECK(listed == present);
  const auto reference = test::reference_dir();
  INFO("the reference (../shared/reference beside the checkout) lists the pages");
  REQUIRE(reference);
  std::set<std::string> pages;
  for (const auto& f : fs::directory_iterator(*reference / "control-tables")) {
    if (f.path().extension() == ".md") {
      pages.insert(f.path().stem().string() + ".json");
    }
  }
  CHECK(listed == pages);
  const auto models = test::catalog_models();
  std::map<std::uint16_t, std::size_t> numbers;
  for (std::size_t i = 0; i < models.size(); ++i) {
    const auto& entry = entries[i];
    INFO(models[i]->name);
    CHECK(entry["name"] == models[i]->name);
    CHECK(entry["file"] == models[i]->name + ".json");
    CHECK(entry["model_number"] == models[i]->model_number);
    // A number reported by two products only where one names the other.
    const auto [first, unique] = numbers.emplace(models[i]->model_number, i);
    if (!unique) {
      const auto& other = *models[first->second];
      INFO("shares " << other.name);
      CHECK((models[i]->shares_model_number_with == other.name ||
             other.shares_model_number_with == models[i]->name));
    }
  }
}

TEST_CASE("Every shipped model matches its reference page row by row", "[model][shipped]") {
  const auto reference = test::reference_dir();
  INFO("the reference (../shared/reference beside the checkout) is needed to cross-check models");
  REQUIRE(reference);
  for (const auto& spec : test::catalog_models()) {
    const auto page =
        test::parse_reference_page(*reference / "control-tables" / (spec->name + ".md"));
    INFO(spec->name);
    REQUIRE(!page.rows.empty());
    const auto notes = item_notes(spec->name);
    std::set<std::uint16_t> matched;
    std::set<std::string> printed_series;
    for (const auto& row : page.rows) {
      INFO(row.name << " at " << row.address);
      printed_series.insert(series_of(row.name));
      const model::ItemSpec* item = nullptr;
      for (const auto& i : spec->items) {
        if (i.address == row.address) {
          item = &i;
        }
      }
      REQUIRE(item != nullptr);
      matched.insert(item->address);
      CHECK(item->name == row.name);
      CHECK(item->size == row.size);
      if (!documented(notes, item->key, "access")) {
        CHECK((item->access == model::Access::ReadOnly ? "R" : "RW") == row.access);
      }
      if (!row.area.empty()) {
        const char* area = item->area == model::Area::Eeprom ? "EEPROM"
                           : item->area == model::Area::Ram  ? "RAM"
                                                             : "Hybrid";
        CHECK(area == row.area);
      }
      const auto initial = test::reference_number(row.initial);
      if (initial && !documented(notes, item->key, "initial")) {
        CHECK(item->initial == *initial);
      }
      const auto tilde = row.range.find('~');
      if (tilde != std::string::npos && row.range.find('~', tilde + 1) == std::string::npos &&
          !documented(notes, item->key, "range")) {
        const auto lo = test::reference_number(row.range.substr(0, tilde));
        const auto hi = test::reference_number(row.range.substr(tilde + 1));
        if (lo && hi) {
          CHECK(item->min == *lo);
          CHECK(item->max == *hi);
        }
      }
    }
    // Items the page does not print belong to a series the page elides ("…"), or are rows its
    // revision lacks, taken from a newer page of the same table (a "row:" note says which).
    for (const auto& item : spec->items) {
      if (matched.count(item.address) == 0 && !documented(notes, item.key, "row")) {
        INFO(item.key << " at " << item.address << " is not on the page");
        CHECK(page.has_elided_rows);
        CHECK(printed_series.count(series_of(item.name)) == 1);
      }
    }
  }
}

TEST_CASE("Every shipped model's initial values read back through the bus as the page prints them",
          "[model][shipped]") {
  const auto reference = test::reference_dir();
  INFO("the reference (../shared/reference beside the checkout) is needed to cross-check models");
  REQUIRE(reference);
  for (const auto& spec : test::catalog_models()) {
    INFO(spec->name);
    model::ControlTable table(spec);
    for (const auto& item : spec->items) {
      INFO(item.key);
      CHECK(read_back(table, item) == item.initial);
    }
    const auto notes = item_notes(spec->name);
    for (const auto& row :
         test::parse_reference_page(*reference / "control-tables" / (spec->name + ".md")).rows) {
      if (const auto initial = test::reference_number(row.initial)) {
        const model::ItemSpec* item = nullptr;
        for (const auto& i : spec->items) {
          item = i.address == row.address ? &i : item;
        }
        REQUIRE(item != nullptr);
        INFO(row.name);
        // As in the row-by-row cross-check: a printed value the item's note overrules (MX 1.0
        // Current: the table prints 0, the description says it idles at 2048).
        if (documented(notes, item->key, "initial")) {
          continue;
        }
        CHECK(read_back(table, *item) == *initial);
      }
    }
  }
}

TEST_CASE("Every shipped model states its motor figures, each with a note naming its source",
          "[model][shipped]") {
  // A figure is in the model with a note naming its source ("motion.<field>...: ..."), or absent
  // with a note saying why ("motion[.:] <field> ... omitted: ..."): the P, PRO and Y pages state no
  // stall figures, the grippers only finger-level ones.
  const auto noted = [](const model::ModelSpec& spec, const std::string& field) {
    return std::any_of(spec.notes.begin(), spec.notes.end(), [&](const std::string& note) {
      return note.rfind("motion.", 0) == 0 && note.find(field) < note.find(':');
    });
  };
  const auto omitted = [](const model::ModelSpec& spec, const std::string& field) {
    return std::any_of(spec.notes.begin(), spec.notes.end(), [&](const std::string& note) {
      const auto colon = note.find(" omitted:");
      return note.rfind("motion", 0) == 0 && colon != std::string::npos && note.find(field) < colon;
    });
  };
  const auto stated = [&](const model::ModelSpec& spec, const std::optional<double>& figure,
                          const std::string& field) {
    INFO(field);
    CHECK((figure ? noted(spec, field) : omitted(spec, field)));
  };
  for (const auto& spec : test::catalog_models()) {
    INFO(spec->name);
    const auto& motion = spec->motion;
    CHECK(motion.nominal_voltage_v);
    CHECK(noted(*spec, "nominal_voltage_v"));
    stated(*spec, motion.no_load_speed_rpm, "no_load_speed_rpm");
    stated(*spec, motion.stall_torque_nm, "stall_torque_nm");
    stated(*spec, motion.stall_current_a, "stall_current_a");
    const bool profile = spec->find("profile_acceleration") != nullptr;
    CHECK(motion.acceleration_unit_rpm2.has_value() == profile);
    CHECK(noted(*spec, "acceleration_unit_rpm2"));
  }
  const auto by_name = [models = test::catalog_models()](const std::string& name) {
    for (const auto& spec : models) {
      if (spec->name == name) {
        return spec;
      }
    }
    throw std::logic_error("no model " + name);
  };
  const auto xm430 = by_name("xm430-w350")->motion;
  CHECK(xm430.no_load_speed_rpm == std::optional(46.0));
  CHECK(xm430.stall_torque_nm == std::optional(4.1));
  CHECK(xm430.stall_current_a == std::optional(2.3));
  CHECK(xm430.nominal_voltage_v == std::optional(12.0));
  CHECK(xm430.acceleration_unit_rpm2 == std::optional(214.577));
  CHECK(by_name("mx-28-2")->motion.acceleration_unit_rpm2 == std::optional(214.577));
  CHECK(by_name("ph54-200-s500-r")->motion.acceleration_unit_rpm2 == std::optional(1.0));
  CHECK(by_name("ax-12a")->motion.nominal_voltage_v == std::optional(12.0));
}

TEST_CASE("Every shipped model has the items its family's drive selects modes with",
          "[model][shipped]") {
  for (const auto& spec : test::catalog_models()) {
    INFO(spec->name << " (" << model::family_name(spec->family) << ")");
    const bool operating_mode = spec->find("operating_mode") != nullptr;
    const bool angle_limits =
        spec->find("cw_angle_limit") != nullptr && spec->find("ccw_angle_limit") != nullptr;
    switch (spec->traits().drive) {
      case model::DriveKind::JointWheel:
        CHECK_FALSE(operating_mode);
        CHECK((angle_limits || spec->find("control_mode") != nullptr));
        CHECK(spec->find("moving_speed") != nullptr);
        CHECK(spec->find("torque_limit") != nullptr);
        break;
      case model::DriveKind::OperatingMode:
        CHECK(operating_mode);
        CHECK_FALSE(angle_limits);
        break;
    }
  }
}

TEST_CASE("The JSON Schema declares exactly the fields the loader accepts", "[model][shipped]") {
  const auto schema = nlohmann::json::parse(slurp(kModels / "schema" / "model.schema.json"));
  auto keys_of = [](const nlohmann::json& properties) {
    std::set<std::string> keys;
    for (auto it = properties.begin(); it != properties.end(); ++it) {
      keys.insert(it.key());
    }
    return keys;
  };
  auto as_set = [](std::span<const std::string_view> fields) {
    return std::set<std::string>(fields.begin(), fields.end());
  };
  CHECK(keys_of(schema.at("properties")) == as_set(model::model_fields()));
  CHECK(keys_of(schema.at("$defs").at("item").at("properties")) == as_set(model::item_fields()));
  CHECK(keys_of(schema.at("$defs").at("motion").at("properties")) ==
        std::set<std::string>{"degrees_per_pulse", "velocity_unit_rpm", "current_unit_ma",
                              "no_load_speed_rpm", "stall_torque_nm", "nominal_voltage_v",
                              "stall_current_a", "acceleration_unit_rpm2", "current_zero"});
}

TEST_CASE("The JSON Schema names the families of the traits table, in its order",
          "[model][shipped]") {
  const auto schema = nlohmann::json::parse(slurp(kModels / "schema" / "model.schema.json"));
  std::string names;
  for (const auto& name : schema.at("properties").at("family").at("enum")) {
    names += (names.empty() ? "" : ", ") + name.get<std::string>();
  }
  CHECK(names == model::family_names());
}
