#include "physics/mujoco_world.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <array>
#include <cstddef>
#include <optional>
#include <set>
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

std::string name_of(const mjModel* model, mjtObj type, int id) {
  const char* name = mj_id2name(model, type, id);
  return name == nullptr ? std::string() : std::string(name);
}

// The drawable geom types by MuJoCo's mjtGeom; nullopt for a height field and anything newer.
std::optional<GeomType> geom_type(int type) {
  switch (type) {
    case mjGEOM_PLANE:
      return GeomType::Plane;
    case mjGEOM_SPHERE:
      return GeomType::Sphere;
    case mjGEOM_CAPSULE:
      return GeomType::Capsule;
    case mjGEOM_ELLIPSOID:
      return GeomType::Ellipsoid;
    case mjGEOM_CYLINDER:
      return GeomType::Cylinder;
    case mjGEOM_BOX:
      return GeomType::Box;
    case mjGEOM_MESH:
      return GeomType::Mesh;
    default:
      return std::nullopt;
  }
}

// A geom's colour as MuJoCo draws it: its material's, unless the geom sets its own rgba (which
// then differs from the default, 0.5 0.5 0.5 1, and takes precedence).
std::array<double, 4> rgba_of(const mjModel* model, int geom) {
  const float* own = model->geom_rgba + 4 * static_cast<std::ptrdiff_t>(geom);
  const bool default_rgba = own[0] == 0.5F && own[1] == 0.5F && own[2] == 0.5F && own[3] == 1.0F;
  const int material = model->geom_matid[geom];
  const float* rgba = material >= 0 && default_rgba
                          ? model->mat_rgba + 4 * static_cast<std::ptrdiff_t>(material)
                          : own;
  return {rgba[0], rgba[1], rgba[2], rgba[3]};
}

// Half-extents and centre, in the mesh's frame (the geom's), of mesh `mesh`'s bounding box.
struct Box {
  std::array<double, 3> half{};
  std::array<double, 3> centre{};
};

Box bounding_box(const mjModel* model, int mesh) {
  const int first = model->mesh_vertadr[mesh];
  const int count = model->mesh_vertnum[mesh];
  std::array<double, 3> low{};
  std::array<double, 3> high{};
  for (int v = 0; v < count; ++v) {
    const float* vertex = model->mesh_vert + 3 * static_cast<std::ptrdiff_t>(first + v);
    for (std::size_t i = 0; i < 3; ++i) {
      const double x = vertex[i];
      low[i] = v == 0 ? x : std::min(low[i], x);
      high[i] = v == 0 ? x : std::max(high[i], x);
    }
  }
  Box box;
  for (std::size_t i = 0; i < 3; ++i) {
    box.half[i] = (high[i] - low[i]) / 2;
    box.centre[i] = (high[i] + low[i]) / 2;
  }
  return box;
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
  describe_geoms();
}

void MujocoWorld::describe_geoms() {
  std::set<std::string> boxed;  // meshes noted as drawn as boxes
  for (int g = 0; g < model_->ngeom; ++g) {
    const auto type = geom_type(model_->geom_type[g]);
    std::string name = name_of(model_, mjOBJ_GEOM, g);
    if (!type) {
      // Appended piece by piece: g++ 12 takes `"#" + std::to_string(g)` for an overlapping
      // copy (-Wrestrict, a false positive) when optimising.
      std::string note = "geom ";
      if (name.empty()) {
        note.append("#").append(std::to_string(g));
      } else {
        note.append("\"").append(name).append("\"");
      }
      scene_.notes.push_back(note.append(" left out: a height field is not drawn"));
      continue;
    }
    GeomShape shape;
    shape.name = std::move(name);
    shape.body = name_of(model_, mjOBJ_BODY, model_->geom_bodyid[g]);
    shape.type = *type;
    shape.rgba = rgba_of(model_, g);
    std::array<double, 3> centre{};
    if (*type == GeomType::Mesh) {
      const int mesh = model_->geom_dataid[g];
      const Box box = bounding_box(model_, mesh);
      shape.size = box.half;
      centre = box.centre;
      shape.mesh = name_of(model_, mjOBJ_MESH, mesh);
      if (boxed.insert(shape.mesh).second) {
        scene_.notes.push_back("mesh \"" + shape.mesh + "\" drawn as its bounding box");
      }
    } else {
      for (std::size_t i = 0; i < 3; ++i) {
        shape.size[i] = model_->geom_size[3 * g + static_cast<int>(i)];
      }
    }
    scene_.geoms.push_back(std::move(shape));
    drawn_.push_back(g);
    centre_.push_back(centre);
  }
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

std::vector<GeomPose> MujocoWorld::geom_poses() {
  // mj_step leaves the poses of the state it integrated from, a step behind qpos: the
  // kinematics of the state now. Deterministic: the next mj_step recomputes them from qpos.
  mj_kinematics(model_, data_);
  std::vector<GeomPose> out;
  out.reserve(drawn_.size());
  for (std::size_t i = 0; i < drawn_.size(); ++i) {
    const mjtNum* pos = data_->geom_xpos + 3 * static_cast<std::ptrdiff_t>(drawn_[i]);
    const mjtNum* mat = data_->geom_xmat + 9 * static_cast<std::ptrdiff_t>(drawn_[i]);
    GeomPose pose;
    for (std::size_t r = 0; r < 3; ++r) {
      pose.pos[r] = pos[r];
      for (std::size_t c = 0; c < 3; ++c) {
        pose.mat[3 * r + c] = mat[3 * r + c];
        pose.pos[r] += mat[3 * r + c] * centre_[i][c];
      }
    }
    out.push_back(pose);
  }
  return out;
}

}  // namespace dxlemu::physics
