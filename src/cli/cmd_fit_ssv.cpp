#include <cstdio>
#include <filesystem>

#include "cli/commands.hpp"
#include "collision/collision_model.hpp"
#include "collision/ssv_fit.hpp"
#include "common/errors.hpp"
#include "io/design_io.hpp"
#include "io/files.hpp"
#include "io/units.hpp"
#include "io/urdf_io.hpp"

namespace armstudy::cli {

void addFitSsvCommand(CLI::App* cmd, Action& action) {
  struct Args {
    std::string design, link, mesh, out;
    bool in_place = false;
    double scale = 1.0, margin_mm = 0;
    int max_volumes = collision::SsvFitOptions{}.max_volumes;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("design", a->design, "Design file (TOML)")->required();
  cmd->add_option("--link", a->link, "Link the mesh belongs to: a joint name or \"base\"")
      ->required();
  cmd->add_option("--mesh", a->mesh,
                  "Closed triangle mesh of the link, .stl or .off, in the link frame")
      ->required();
  cmd->add_option("--out", a->out, "Output design file (default: <design>.fitted.toml beside it)");
  cmd->add_flag("--in-place", a->in_place, "Rewrite the design file itself (atomically)");
  cmd->add_option("--scale", a->scale,
                  "Mesh units to metres, e.g. 0.001 for millimetres (default 1)");
  cmd->add_option("--max-volumes", a->max_volumes, "Most SSVs to use for the link (default 4)");
  cmd->add_option("--margin-mm", a->margin_mm,
                  "Extra clearance added to every radius [mm] (default 0)");
  setAction(cmd, action, [a] {
    if (a->in_place && !a->out.empty())
      throw InputError("--out", 0, "out", "use either --out or --in-place, not both");
    if (isUrdfPath(a->design))
      throw InputError(
          a->design, 0, "design",
          "fit-ssv rewrites a design TOML; a URDF's volumes are fitted to its collision geometry "
          "on import: convert it first (armstudy convert X.urdf X.toml) and fit into the TOML");
    const std::string text = readFileOrThrow(a->design);
    const Model m = parseDesign(text, a->design);
    if (collision::bodyIndex(m, a->link) < -1)
      throw InputError(a->design, 0, "--link",
                       "no link named '" + a->link + "' in design '" + m.name +
                           "' (use a joint name or \"base\")");
    collision::SsvFitOptions o;
    o.max_volumes = a->max_volumes;
    o.margin_m = a->margin_mm * 1e-3;
    if (const std::string err = o.validate(); !err.empty())
      throw InputError("--max-volumes", 0, "fit-ssv", err);
    const collision::TriangleMesh mesh =
        collision::loadTriangleMesh(a->mesh, a->scale, kMaxLength_m);
    const collision::SsvFitSummary fit = collision::fitSsvs(mesh, o);
    const std::string label = std::filesystem::path(a->mesh).filename().string() + " (" +
                              fileHash(a->mesh) + ", scale " + std::to_string(a->scale) + ")";
    const std::string new_text =
        collision::replaceLinkVolumesInDesignText(text, a->link, fit.volumes, label);
    std::string out = a->in_place ? a->design : a->out;
    if (out.empty()) {
      std::filesystem::path p(a->design);
      out = (p.parent_path() / (p.stem().string() + ".fitted.toml")).string();
    }
    parseDesign(new_text, out);  // the written design must load
    writeFileAtomic(out, new_text);
    std::printf(
        "fitted %zu SSV(s) to %s (%d vertices, %d slab(s)): swept volume %.6f m^3 for a mesh "
        "volume "
        "of %.6f m^3; farthest vertex %.3g m inside\n",
        fit.volumes.size(), a->mesh.c_str(), fit.mesh_vertices, fit.slabs, fit.swept_volume_m3,
        fit.mesh_volume_m3, -fit.max_vertex_excess_m);
    for (const auto& v : fit.volumes)
      std::printf("  %-8s radius %.4f m\n", toString(v.type), v.radius_m);
    std::printf("wrote %s\n", out.c_str());
    return 0;
  });
}

}  // namespace armstudy::cli
