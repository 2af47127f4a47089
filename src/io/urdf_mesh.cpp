#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <assimp/Importer.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "collision/collision.hpp"
#include "collision/ssv_fit.hpp"
#include "common/errors.hpp"
#include "io/files.hpp"
#include "io/units.hpp"
#include "io/urdf_internal.hpp"
#include "kinematics/kinematics.hpp"

namespace armstudy::urdf_detail {

namespace fs = std::filesystem;
using Eigen::Isometry3d;
using Eigen::Matrix3d;
using Eigen::Vector3d;

Isometry3d toIso(const urdf::Pose& p) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() =
      Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z).toRotationMatrix();
  T.translation() = Vector3d(p.position.x, p.position.y, p.position.z);
  return T;
}

namespace {

// package://NAME/rest: --package NAME=DIR first, then the folders above the URDF file (the first
// A with A/rest or A/NAME/rest). file:// URIs are absolute, plain names relative to the URDF.
// Unresolved: "" with the reason in `error` (the package, the packages given, the folders tried).
std::string resolveMesh(const std::string& uri, const std::string& urdf_file, const UrdfOptions& o,
                        std::string& error) {
  const fs::path urdf_dir = fs::absolute(fs::path(urdf_file)).parent_path();
  const std::string pkg = "package://", file = "file://";
  if (uri.rfind(pkg, 0) == 0) {
    const std::string s = uri.substr(pkg.size());
    const auto slash = s.find('/');
    const std::string name = s.substr(0, slash),
                      rest = slash == std::string::npos ? "" : s.substr(slash + 1);
    std::string given;
    for (const auto& [n, dir] : o.packages) {
      if (n == name) return (fs::path(dir) / rest).string();
      given += (given.empty() ? "" : ", ") + n;
    }
    fs::path top = urdf_dir;
    for (fs::path a = urdf_dir; !a.empty(); a = a.parent_path()) {
      if (fs::exists(a / rest)) return (a / rest).string();
      if (fs::exists(a / name / rest)) return (a / name / rest).string();
      top = a;
      if (a == a.parent_path()) break;
    }
    error = "package '" + name + "' not found: no --package " + name +
            "=DIR (packages given: " + (given.empty() ? "none" : given) +
            "), and no folder A from " + urdf_dir.string() + " up to " + top.string() + " has A/" +
            rest + " or A/" + name + "/" + rest + " (give --package " + name +
            "=DIR; packages in a study)";
    return "";
  }
  if (uri.rfind(file, 0) == 0) return uri.substr(file.size());
  const fs::path p(uri);
  return p.is_absolute() ? p.string() : (urdf_dir / p).string();
}

// Where a link's <collision> element is, for messages: the URDF file, the link's line, the key.
struct CollisionSite {
  const std::string& file;
  int line;
  std::string key;  // link 'NAME'/collision
};

// The bytes of the mesh file at `path` (which exists). A file that is not regular (a FIFO, a
// device: a read could block forever), that is empty (so also a kernel file of /proc that reads as
// empty and may never end) or that is larger than defaults::kMaxMeshFileBytes (reading and fitting
// an STL takes about 43 bytes of memory per byte of it) is an InputError at the link.
std::string readMeshFile(const std::string& path, const std::string& uri, const CollisionSite& at) {
  const std::string what = "mesh '" + uri + "' (" + path + "): ";
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) {
    const auto size = fs::file_size(path, ec);
    if (!ec && size == 0)
      throw InputError(at.file, at.line, at.key,
                       what +
                           "the file is empty (files of /proc and /sys read as empty; a mesh "
                           "must be a regular file with content)");
    if (!ec && size > defaults::kMaxMeshFileBytes)
      throw InputError(at.file, at.line, at.key,
                       what + "file of " + std::to_string(size) +
                           " bytes exceeds the limit for a collision mesh of " +
                           std::to_string(defaults::kMaxMeshFileBytes) +
                           " bytes (simplify the mesh; README \"Input limits\")");
  }
  try {
    return readFileOrThrow(path);  // refuses FIFOs, devices and folders
  } catch (const InputError& e) {
    throw InputError(at.file, at.line, at.key, what + e.message());
  }
}

// All triangles of a mesh file's bytes (STL, DAE, OBJ, ... through assimp; the file name's
// extension tells the format), node transforms applied.
bool loadMesh(const std::string& bytes, const std::string& path, collision::TriangleMesh& out,
              std::string& error) {
  std::string ext = fs::path(path).extension().string();
  if (!ext.empty()) ext.erase(0, 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  Assimp::Importer imp;
  // Assumption: a DAE's up axis is ignored, as ROS tools do with URDF meshes; unit scale applies.
  imp.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* sc =
      imp.ReadFileFromMemory(bytes.data(), bytes.size(),
                             aiProcess_Triangulate | aiProcess_JoinIdenticalVertices, ext.c_str());
  if (!sc || !sc->mRootNode) {
    error = std::string("assimp cannot read it: ") + imp.GetErrorString();
    return false;
  }
  std::vector<std::pair<const aiNode*, aiMatrix4x4>> stack{
      {sc->mRootNode, sc->mRootNode->mTransformation}};
  while (!stack.empty()) {
    auto [node, T] = stack.back();
    stack.pop_back();
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      const aiMesh* mesh = sc->mMeshes[node->mMeshes[k]];
      const int first = static_cast<int>(out.vertices.size());
      for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
        const aiVector3D p = T * mesh->mVertices[v];
        out.vertices.emplace_back(p.x, p.y, p.z);
      }
      for (unsigned f = 0; f < mesh->mNumFaces; ++f)
        if (mesh->mFaces[f].mNumIndices == 3)
          out.triangles.push_back({first + static_cast<int>(mesh->mFaces[f].mIndices[0]),
                                   first + static_cast<int>(mesh->mFaces[f].mIndices[1]),
                                   first + static_cast<int>(mesh->mFaces[f].mIndices[2])});
    }
    for (unsigned c = 0; c < node->mNumChildren; ++c)
      stack.push_back({node->mChildren[c], T * node->mChildren[c]->mTransformation});
  }
  if (out.vertices.empty()) {
    error = "the mesh has no vertices";
    return false;
  }
  return true;
}

// An InputError at the link unless every point is finite and within the plausible length
// (io/units.hpp) of the frame's origin; `what` names the points ("mesh 'x.stl' (scaled)").
void requirePlausible(const std::vector<Vector3d>& points, const std::string& what,
                      const CollisionSite& at) {
  const std::string problem = collision::meshVertexProblem(points, kMaxLength_m);
  if (!problem.empty()) throw InputError(at.file, at.line, at.key, what + ": " + problem);
}

void addFitted(Model& m, int body, const std::string& name, const collision::SsvFitSummary& fit) {
  int k = 0;
  for (const auto& f : fit.volumes) {
    CollisionVolume v;
    v.name = name + (fit.volumes.size() > 1 ? "_" + std::to_string(k++) : "");
    v.link = body;
    v.type = f.type;
    v.p_L = f.p;
    v.radius_m = f.radius_m;
    m.collision.volumes.push_back(v);
  }
}

}  // namespace

namespace {

// The box of side lengths `b` placed by T, as a closed triangle mesh.
collision::TriangleMesh boxMesh(const urdf::Box& b, const Isometry3d& T) {
  collision::TriangleMesh tm;
  for (int k = 0; k < 8; ++k)
    tm.vertices.push_back(T * Vector3d((k & 1 ? 0.5 : -0.5) * b.dim.x,
                                       (k & 2 ? 0.5 : -0.5) * b.dim.y,
                                       (k & 4 ? 0.5 : -0.5) * b.dim.z));
  // 12 triangles of the box (corner k has bit 0 = +x, bit 1 = +y, bit 2 = +z)
  tm.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                  {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return tm;
}

// The mesh file of `me`, scaled and placed by T, into `tm`. A mesh that cannot be found or read
// is a warning (false); a special, empty or too large file and vertices that are not finite or not
// plausible are InputErrors at the link.
bool fileMesh(const urdf::Mesh& me, const Isometry3d& T, const std::string& link,
              const std::string& file, const UrdfOptions& o, const CollisionSite& at,
              std::vector<std::string>& warnings, std::string& mesh_hashes,
              collision::TriangleMesh& tm) {
  std::string err;
  const std::string path = resolveMesh(me.filename, file, o, err);
  std::error_code ec;
  if (!path.empty() && !fs::exists(path, ec)) err = "mesh file not found (tried " + path + ")";
  collision::TriangleMesh raw;
  std::string bytes;
  if (err.empty()) bytes = readMeshFile(path, me.filename, at);
  if (const auto b = bytes.find_first_not_of(" \t\r\n");
      b != std::string::npos && bytes[b] == '<') {
    try {  // an XML mesh (DAE): assimp's reader recurses once per level, as TinyXML does
      scanXmlTags(bytes, path);
    } catch (const InputError& e) {
      throw InputError(at.file, at.line, at.key,
                       "mesh '" + me.filename + "' (" + path + ":" + std::to_string(e.line()) +
                           "): " + e.message());
    }
  }
  if (!err.empty() || !loadMesh(bytes, path, raw, err)) {
    warnings.push_back("URDF import: link '" + link + "' gets no collision volume from mesh '" +
                       me.filename + "': " + err);
    return false;
  }
  mesh_hashes += me.filename + " " + contentHash(bytes) + "\n";
  const Vector3d scale(me.scale.x, me.scale.y, me.scale.z);
  for (Vector3d& p : raw.vertices) p = p.cwiseProduct(scale);
  requirePlausible(raw.vertices, "mesh '" + me.filename + "' (scaled, in its <collision> frame)",
                   at);
  tm.triangles = raw.triangles;
  for (const Vector3d& p : raw.vertices) tm.vertices.push_back(T * p);
  return true;
}

}  // namespace

void addCollision(Model& m, int body, const LinkInBody& lb, const std::string& file,
                  const UrdfOptions& o, const XmlIndex& xml, std::vector<std::string>& warnings,
                  std::string& mesh_hashes) {
  int idx = 0;
  for (const auto& c : lb.link->collision_array) {
    if (!c || !c->geometry) continue;
    const std::string name =
        lb.link->name + (lb.link->collision_array.size() > 1 ? "_c" + std::to_string(idx) : "");
    ++idx;
    const int line = xml.links.count(lb.link->name) ? xml.links.at(lb.link->name) : 0;
    const CollisionSite at{file, line, "link '" + lb.link->name + "'/collision"};
    const Isometry3d T = lb.T_FL * toIso(c->origin);
    // Each number is plausible (indexAndCheck); the geometry placed in the body frame (the fixed
    // joints' origins before it included) must be too.
    const std::string placed = "the collision geometry placed in the body frame";
    collision::TriangleMesh tm;
    switch (c->geometry->type) {
      case urdf::Geometry::SPHERE: {
        const auto& s = static_cast<const urdf::Sphere&>(*c->geometry);
        CollisionVolume v;
        v.name = name;
        v.link = body;
        v.type = SsvType::Point;
        v.p_L[0] = T.translation();
        v.radius_m = s.radius;
        v.source_line = line;
        requirePlausible({v.p_L[0]}, placed, at);
        m.collision.volumes.push_back(v);
        continue;
      }
      case urdf::Geometry::CYLINDER: {  // a capsule on the cylinder's axis: contains the cylinder
        const auto& s = static_cast<const urdf::Cylinder&>(*c->geometry);
        CollisionVolume v;
        v.name = name;
        v.link = body;
        v.type = s.length > 0 ? SsvType::Line : SsvType::Point;
        v.p_L[0] = T * Vector3d(0, 0, -s.length / 2);
        v.p_L[1] = T * Vector3d(0, 0, s.length / 2);
        if (v.type == SsvType::Point) v.p_L[0] = T.translation();
        v.radius_m = s.radius;
        v.source_line = line;
        requirePlausible({v.p_L[0], v.p_L[1]}, placed, at);
        m.collision.volumes.push_back(v);
        continue;
      }
      case urdf::Geometry::BOX:
        tm = boxMesh(static_cast<const urdf::Box&>(*c->geometry), T);
        break;
      case urdf::Geometry::MESH:
        if (!fileMesh(static_cast<const urdf::Mesh&>(*c->geometry), T, lb.link->name, file, o, at,
                      warnings, mesh_hashes, tm))
          continue;
        break;
      default:
        continue;
    }
    requirePlausible(tm.vertices, placed, at);
    collision::SsvFitOptions fo;
    fo.max_volumes = defaults::kUrdfSsvMaxVolumesPerMesh;
    const std::size_t before = m.collision.volumes.size();
    addFitted(m, body, name, collision::fitSsvs(tm, fo));
    for (std::size_t k = before; k < m.collision.volumes.size(); ++k)
      m.collision.volumes[k].source_line = line;
  }
}

}  // namespace armstudy::urdf_detail
