#include "physics/mujoco_world.hpp"

#include <mujoco/mujoco.h>

#include <array>
#include <string>
#include <vector>

#include "physics/mjcf_world.hpp"

namespace dxlemu::physics {
namespace {

// mj_loadXML's error buffer: MuJoCo's messages are one line.
constexpr std::size_t kErrorLength = 1024;

// MuJoCo's default handlers print, write MUJOCO_LOG.TXT into the working directory, and on an
// error exit the process. dxlemu reports errors itself and keeps warnings off the terminal the
// client's session may share; a warning that matters (an unstable model) shows in the motion.
void on_mujoco_error(const char* message) {
  throw PhysicsError(std::string("MuJoCo: ") + message);
}

void on_mujoco_warning(const char* /*message*/) {}

void install_handlers() {
  mju_user_error = on_mujoco_error;
  mju_user_warning = on_mujoco_warning;
}

bool one_dof(int type) {
  return type == mjJNT_HINGE || type == mjJNT_SLIDE;
}

}  // namespace

MujocoWorld::MujocoWorld(const std::filesystem::path& file, double timestep_s) {
  install_handlers();
  std::array<char, kErrorLength> error{};
  model_ = mj_loadXML(file.c_str(), nullptr, error.data(), static_cast<int>(error.size()));
  if (model_ == nullptr) {
    throw PhysicsError(std::string("MuJoCo cannot load it: ") + error.data());
  }
  model_->opt.timestep = timestep_s;
  data_ = mj_makeData(model_);
  if (data_ == nullptr) {
    mj_deleteModel(model_);
    throw PhysicsError("MuJoCo cannot allocate its data");
  }
  actuator_.assign(static_cast<std::size_t>(model_->nv), 0.0);
  external_.assign(static_cast<std::size_t>(model_->nv), 0.0);
  // Positions and velocities of the initial state, before the first step.
  mj_forward(model_, data_);
}

MujocoWorld::~MujocoWorld() {
  mj_deleteData(data_);
  mj_deleteModel(model_);
}

std::string MujocoWorld::engine() {
  return std::string("MuJoCo ") + mj_versionString();
}

std::optional<std::size_t> MujocoWorld::find_joint(std::string_view name) const {
  const std::string key(name);
  const int id = mj_name2id(model_, mjOBJ_JOINT, key.c_str());
  if (id < 0 || !one_dof(model_->jnt_type[id])) {
    return std::nullopt;
  }
  return static_cast<std::size_t>(id);
}

std::vector<std::string> MujocoWorld::joints() const {
  std::vector<std::string> out;
  for (int j = 0; j < model_->njnt; ++j) {
    const char* name = mj_id2name(model_, mjOBJ_JOINT, j);
    if (name != nullptr && one_dof(model_->jnt_type[j])) {
      out.emplace_back(name);
    }
  }
  return out;
}

std::optional<std::size_t> MujocoWorld::find_body(std::string_view name) const {
  const std::string key(name);
  const int id = mj_name2id(model_, mjOBJ_BODY, key.c_str());
  if (id < 0) {
    return std::nullopt;
  }
  return static_cast<std::size_t>(id);
}

std::vector<std::string> MujocoWorld::bodies() const {
  std::vector<std::string> out;
  for (int b = 0; b < model_->nbody; ++b) {
    if (const char* name = mj_id2name(model_, mjOBJ_BODY, b); name != nullptr) {
      out.emplace_back(name);
    }
  }
  return out;
}

double MujocoWorld::timestep_s() const {
  return model_->opt.timestep;
}

void MujocoWorld::add_armature(std::size_t joint, double kg_m2) {
  model_->dof_armature[model_->jnt_dofadr[joint]] += kg_m2;
}

void MujocoWorld::apply(std::size_t dof) {
  data_->qfrc_applied[dof] = actuator_[dof] + external_[dof];
}

void MujocoWorld::set_torque(std::size_t joint, double torque_nm) {
  const auto dof = static_cast<std::size_t>(model_->jnt_dofadr[joint]);
  actuator_[dof] = torque_nm;
  apply(dof);
}

void MujocoWorld::set_external_torque(std::size_t joint, double torque_nm) {
  const auto dof = static_cast<std::size_t>(model_->jnt_dofadr[joint]);
  external_[dof] = torque_nm;
  apply(dof);
}

void MujocoWorld::set_wrench(std::size_t body, const Wrench& wrench) {
  // xfrc_applied: per body, a force then a torque, at the centre of mass, world frame.
  mjtNum* out = data_->xfrc_applied + 6 * body;
  for (std::size_t i = 0; i < 3; ++i) {
    out[i] = wrench.force[i];
    out[3 + i] = wrench.torque[i];
  }
}

Wrench MujocoWorld::wrench(std::size_t body) const {
  const mjtNum* in = data_->xfrc_applied + 6 * body;
  Wrench w;
  for (std::size_t i = 0; i < 3; ++i) {
    w.force[i] = in[i];
    w.torque[i] = in[3 + i];
  }
  return w;
}

void MujocoWorld::step() {
  mj_step(model_, data_);
}

JointState MujocoWorld::joint(std::size_t joint) const {
  return {data_->qpos[model_->jnt_qposadr[joint]], data_->qvel[model_->jnt_dofadr[joint]]};
}

JointForces MujocoWorld::forces(std::size_t joint) const {
  // mj_step leaves the forces of the state it integrated from: those of the last step.
  const auto dof = static_cast<std::size_t>(model_->jnt_dofadr[joint]);
  return {actuator_[dof], external_[dof], data_->qfrc_constraint[dof], data_->qfrc_bias[dof]};
}

}  // namespace dxlemu::physics
