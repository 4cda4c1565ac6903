#include "arm_rig.hpp"

#include <mujoco/mujoco.h>

#include <array>
#include <stdexcept>

#include "app/config/make_servo.hpp"
#include "app/config/physics_config.hpp"
#include "app/config/robot_library.hpp"

namespace dxlemu::test {

const app::ModelLibrary& shipped_library() {
  static const app::ModelLibrary library = app::ModelLibrary::load(DXLEMU_MODELS_DIR, {});
  return library;
}

app::BusConfig profile_with_physics(const std::filesystem::path& profile,
                                    const std::filesystem::path& physics) {
  // What `dxlemu run --config PROFILE --physics PHYSICS` serves.
  app::BusConfig config = app::read_config(profile, shipped_library());
  app::attach_physics(config, physics);
  return config;
}

ArmRig::ArmRig(const app::BusConfig& config, bool with_physics, sim::SimDuration tick) {
  for (const app::PortConfig& port : config.ports) {
    for (const app::ServoConfig& s : port.servos) {
      servos_.push_back(app::make_servo(shipped_library(), s, tick));
    }
  }
  if (!with_physics || !config.physics) {
    return;
  }
  clock_ = app::load_physics(*config.physics, tick);
  for (std::size_t i = 0; i < config.physics->joints.size(); ++i) {
    // One port per shipped arm: the joint's ID names its servo.
    servo(config.physics->joints[i].id)
        .motion()
        .couple(*clock_, app::joint_mapping(*config.physics, i, clock_->world()));
  }
}

model::Servo& ArmRig::servo(std::uint8_t id) {
  for (auto& s : servos_) {
    if (s->id() == id) {
      return *s;
    }
  }
  throw std::out_of_range("no servo " + std::to_string(id));
}

void ArmRig::wait(sim::SimDuration d) {
  now_ += d;
  for (auto& s : servos_) {
    s->advance_to(now_);
  }
}

std::int64_t ArmRig::get(std::uint8_t id, const std::string& key) {
  const model::Servo& s = servo(id);
  return s.table().get(s.table().index(key));
}

void ArmRig::set(std::uint8_t id, const std::string& key, std::int64_t value) {
  model::Servo& s = servo(id);
  s.advance_to(now_);
  s.device_write(s.table().index(key), value);
}

std::vector<std::uint8_t> ArmRig::table_bytes() const {
  std::vector<std::uint8_t> bytes;
  for (const auto& s : servos_) {
    const auto table = s->table().bytes();
    bytes.insert(bytes.end(), table.begin(), table.end());
  }
  return bytes;
}

std::map<std::string, double> holding_forces(const std::filesystem::path& mjcf,
                                             const std::map<std::string, double>& qpos) {
  constexpr int kErrorSize = 1000;
  std::array<char, kErrorSize> error{};
  mjModel* m = mj_loadXML(mjcf.c_str(), nullptr, error.data(), kErrorSize);
  if (m == nullptr) {
    throw std::runtime_error(mjcf.string() + ": " + error.data());
  }
  mjData* d = mj_makeData(m);
  for (const auto& [name, value] : qpos) {
    const int joint = mj_name2id(m, mjOBJ_JOINT, name.c_str());
    if (joint < 0) {
      throw std::runtime_error(mjcf.string() + " has no joint " + name);
    }
    d->qpos[m->jnt_qposadr[joint]] = value;
  }
  // At rest qfrc_bias is gravity's pull alone (no Coriolis terms): what the joint must apply.
  mj_forward(m, d);
  std::map<std::string, double> forces;
  for (int j = 0; j < m->njnt; ++j) {
    forces[mj_id2name(m, mjOBJ_JOINT, j)] = d->qfrc_bias[m->jnt_dofadr[j]];
  }
  mj_deleteData(d);
  mj_deleteModel(m);
  return forces;
}

}  // namespace dxlemu::test
