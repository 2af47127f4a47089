// A reach grid's output is rendered in pieces, each by the process that owns it, and joined in
// piece order (study/rendered_part.hpp): the join must read every piece exactly once, in the order
// one process would write them, and each piece must render what the join takes it for. Checked
// against the join order spelled out here (each design's main piece, its surfaces, its figures;
// then the pairs' images) and against the counts of compared pairs in closed form.
#include "stages/reach/reach_grid_pieces.hpp"

#include <catch2/catch.hpp>
#include <cstddef>
#include <vector>

#include "stages/reach/reach_grid_results.hpp"

using namespace armstudy;

namespace {

// A grid of 3 x 2 positions (2-D, or 3-D with `layers` > 1) in `orientations` orientations, with
// `designs` (empty) maps: what gridPieces reads of the results.
ReachGridResults gridOf(TaskGrid& g, std::size_t designs, int orientations, int layers) {
  g.name = "pieces";
  g.axes[0] = {0.0, 0.2, 0.1};
  g.axes[1] = {0.0, 0.1, 0.1};
  g.axes[2] = {0.0, 0.1 * (layers - 1), 0.1};
  g.orientations.assign(static_cast<std::size_t>(orientations), Orientation{});
  ReachGridResults res;
  res.grid = &g;
  res.dims = g.dims();
  res.positions = g.points();
  res.orientation_count = orientations;
  res.maps.resize(designs);
  res.pairs = comparedPairs(designs);
  return res;
}

// The pieces in the order the report joins them.
std::vector<std::size_t> joinOrder(const GridPieces& pieces) {
  std::vector<std::size_t> order;
  for (std::size_t di = 0; di < pieces.design_count; ++di) {
    order.push_back(pieces.mainPiece(di));
    for (int k = 0; k < pieces.orientation_count; ++k) order.push_back(pieces.surfacePiece(di, k));
    for (int k = 0; k < pieces.orientation_count; ++k) order.push_back(pieces.figuresPiece(di, k));
  }
  if (pieces.pair_images)
    for (std::size_t i = 0; i < pieces.image_pairs.size(); ++i)
      order.push_back(pieces.pairPiece(i));
  return order;
}

}  // namespace

TEST_CASE("reach grid pieces: the join reads each piece once, in piece order, as what it renders",
          "[reach]") {
  for (const std::size_t designs : {1, 2, 4, 5, 13})
    for (const int orientations : {1, 3}) {
      TaskGrid g;
      const ReachGridResults res = gridOf(g, designs, orientations, 1);
      const GridPieces pieces = gridPieces(res, ReachConfig{});
      const std::vector<std::size_t> order = joinOrder(pieces);
      REQUIRE(order.size() == pieces.count());
      for (std::size_t i = 0; i < order.size(); ++i) REQUIRE(order[i] == i);
      std::size_t it = 0;
      for (std::size_t di = 0; di < designs; ++di) {
        const GridPiece main = pieces.piece(it++);
        CHECK(main.kind == GridPiece::Kind::Main);
        CHECK(main.design == di);
        for (const GridPiece::Kind kind : {GridPiece::Kind::Surface, GridPiece::Kind::Figures})
          for (int k = 0; k < orientations; ++k) {
            const GridPiece p = pieces.piece(it++);
            CHECK(p.kind == kind);
            CHECK(p.design == di);
            CHECK(p.orientation == k);
          }
      }
      for (std::size_t i = 0; it < pieces.count(); ++i) {
        const GridPiece p = pieces.piece(it++);
        CHECK(p.kind == GridPiece::Kind::PairImages);
        CHECK(p.pair == i);
      }
    }
}

TEST_CASE("reach grid pieces: every pair compared up to 12 designs, images of every pair up to 4",
          "[reach]") {
  for (std::size_t n = 1; n <= 15; ++n) {
    TaskGrid g;
    const ReachGridResults res = gridOf(g, n, 2, 1);
    const std::size_t all_pairs = n * (n - 1) / 2;
    CHECK(res.pairs.size() == (n <= kMaxComparedDesigns ? all_pairs : n - 1));
    const GridPieces pieces = gridPieces(res, ReachConfig{});
    CHECK(pieces.pair_images == (n >= 2));
    CHECK(pieces.image_pairs.size() == (n <= kMaxPairImageDesigns ? res.pairs.size() : n - 1));
    for (const std::size_t p : pieces.image_pairs)
      CHECK((n <= kMaxPairImageDesigns || res.pairs[p].first == 0));
    CHECK(pieces.count() == n * 5 + (n >= 2 ? pieces.image_pairs.size() : 0));
  }
  // No pair images for a 3-D grid (its figures project an axis out) or without images.
  TaskGrid g3;
  const ReachGridResults res3 = gridOf(g3, 3, 1, 2);
  CHECK_FALSE(gridPieces(res3, ReachConfig{}).pair_images);
  TaskGrid g2;
  ReachConfig no_images;
  no_images.outputs.images = false;
  CHECK_FALSE(gridPieces(gridOf(g2, 3, 1, 1), no_images).pair_images);
}
