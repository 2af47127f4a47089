#pragma once
// A task grid's output cut into pieces (private to stages/reach), each rendered on its own from
// the grid's computed results: per design, piece 0 its summary entry, report lines, table rows, VTK
// map and best robot; pieces 1..n its boundary surface in each of the n orientations (3-D grids);
// pieces n+1..2n its status and manipulability figures in each orientation; then, per compared
// pair that gets images, the pair's images. Joined in piece order, the files are in the order one
// call would write them (study/rendered_part.hpp).
#include <cstddef>
#include <string>
#include <vector>

#include "stages/reach/reach_config.hpp"
#include "stages/reach/reach_grid_results.hpp"
#include "stages/reach/reach_report.hpp"
#include "study/stage.hpp"

namespace armstudy {

// Pair images (one per orientation and pair) for all pairs up to this many designs; beyond, for
// the first design against each other.
constexpr std::size_t kMaxPairImageDesigns = 4;

// What one piece renders: design `design`'s main piece, or its surface or figures in orientation
// `orientation`, or the images of the pair image_pairs[pair].
struct GridPiece {
  enum class Kind { Main, Surface, Figures, PairImages } kind = Kind::Main;
  std::size_t design = 0;
  int orientation = 0;
  std::size_t pair = 0;
};

struct GridPieces {
  reach_report::ImagePlane plane;  // the figures' axes
  int image_rows = 1;              // cells along the figures' second axis
  int orientation_count = 1;       // the grid's
  std::size_t design_count = 0;
  std::vector<std::size_t> image_pairs;  // the pairs (indices into ReachGridResults::pairs) ...
  bool pair_images = false;              // ... and whether they get images at all
  int piecesPerDesign() const { return 1 + 2 * orientation_count; }
  std::size_t designPieces() const {
    return design_count * static_cast<std::size_t>(piecesPerDesign());
  }
  std::size_t count() const { return designPieces() + (pair_images ? image_pairs.size() : 0); }
  // The pieces of design di: its main piece, its surface and its figures in orientation k; the
  // images of the i-th pair in image_pairs.
  std::size_t mainPiece(std::size_t di) const {
    return di * static_cast<std::size_t>(piecesPerDesign());
  }
  std::size_t surfacePiece(std::size_t di, int k) const {
    return mainPiece(di) + 1 + static_cast<std::size_t>(k);
  }
  std::size_t figuresPiece(std::size_t di, int k) const {
    return mainPiece(di) + 1 + static_cast<std::size_t>(orientation_count + k);
  }
  std::size_t pairPiece(std::size_t i) const { return designPieces() + i; }
  // The inverse: what piece `it` (< count()) renders.
  GridPiece piece(std::size_t it) const;
};

GridPieces gridPieces(const ReachGridResults& res, const ReachConfig& cfg);

// What every piece is rendered from: the run, the settings, the grid's results and their pieces.
struct GridRendering {
  const StageContext& ctx;
  const ReachConfig& cfg;
  const ReachGridResults& res;
  const TaskGrid& grid;  // res.taskGrid()
  const GridPieces& layout;
};

// Renders every piece in a loop shared among the processes of ctx.units, each piece by the
// process that owns it, which writes its files into the study's output folder (ctx.resultsDir())
// itself. Returns every piece's part as bytes (study/rendered_part.hpp), in piece order.
std::vector<std::string> renderGridPieces(const StageContext& ctx, const ReachConfig& cfg,
                                          const ReachGridResults& res, const GridPieces& pieces);

}  // namespace armstudy
