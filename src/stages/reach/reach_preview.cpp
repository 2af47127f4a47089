#include "stages/reach/reach_preview.hpp"

#include "stages/reach/reach_report.hpp"
#include "study/rendered_part.hpp"

// Progressive reach maps (RunOptions::preview_stride; docs/reachability.md, "Progressive maps").
namespace armstudy {

namespace {

// Samples 0, k, 2k, ... of a range (a single value stays as it is).
AxisRange everyKth(const AxisRange& a, int k) {
  const int n = a.count();
  if (n <= 1 || k <= 1) return a;
  const int m = (n - 1) / k + 1;
  AxisRange out;
  out.from = a.from;
  out.step = a.step * k;
  out.to = a.from + (m - 1) * out.step;
  return out;
}

}  // namespace

TaskGrid previewGrid(const TaskGrid& g, int k) {
  TaskGrid c = g;
  for (AxisRange& a : c.axes) a = everyKth(a, k);
  return c;
}

std::vector<std::string> writeReachPreviews(const StageContext& ctx, const ReachConfig& cfg) {
  using namespace reach_report;
  const int k = ctx.options.preview_stride;
  const std::size_t designs = ctx.study.designs.size();
  std::vector<std::string> files;
  for (const TaskGrid& full : cfg.grids) {
    const TaskGrid g = previewGrid(full, k);
    const ImagePlane plane = imagePlane(g);
    const std::string note =
        " (preview: 1 in " + std::to_string(k) + " values along each axis, before the map search)";
    const std::vector<std::string> parts = renderShared(
        &ctx.units, "preview/reach/" + g.name, designs, ctx.threads, [&](std::size_t di) {
          const Model& model = ctx.study.designs[di].model;
          const PoseSweep map = sweepGrid(model, g, cfg.ik, 1, nullptr, cfg.collisionFor(model));
          Writer out(ctx.resultsDir());
          for (int o = 0; o < static_cast<int>(g.orientations.size()); ++o) {
            std::array<long, kReachStatusCount> counts{};
            for (long p = 0; p < g.points(); ++p) ++counts[map.status[o * g.points() + p]];
            const std::string stem = "reach/preview/" + g.name + "__" + model.name + suffix(g, o);
            writeStatusFigure(out, stem, g, plane, map, o, counts,
                              model.name + ", " + orientationText(g, o) + note);
            if (ctx.options.on_preview) ctx.options.on_preview(out.path(stem + ".png"));
          }
          return packRenderedPart(RenderedPart{}, out);
        });
    for (const std::string& bytes : parts) {
      RenderedPart part;
      unpackRenderedPart(bytes, part, files);
    }
  }
  return files;
}

}  // namespace armstudy
