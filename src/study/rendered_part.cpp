#include "study/rendered_part.hpp"

#include <cstdint>
#include <string_view>

#include "common/errors.hpp"
#include "common/parallel_for.hpp"
#include "study/checkpoint.hpp"
#include "study/shared_loop.hpp"

namespace armstudy {

namespace {
constexpr std::string_view kPartMagic = "armstudy-rendered-part-1";
constexpr std::string_view kPartsMagic = "armstudy-rendered-parts-1";
}  // namespace

std::string packRenderedPart(const RenderedPart& part, const Writer& w) {
  UnitWriter b(kPartMagic);
  b.putVector(nlohmann::ordered_json::to_cbor(part.jd));
  b.putString(part.md);
  b.putString(part.images_md);
  b.put<std::uint64_t>(part.rows.size());
  for (const auto& row : part.rows) {
    b.put<std::uint64_t>(row.size());
    for (const std::string& c : row) b.putString(c);
  }
  b.put<std::uint64_t>(w.files().size());
  for (const std::string& rel : w.files()) b.putString(rel);
  return b.bytes();
}

void unpackRenderedPart(const std::string& bytes, RenderedPart& part,
                        std::vector<std::string>& files) {
  UnitReader rd(bytes, kPartMagic);
  std::vector<std::uint8_t> cbor;
  rd.getVector(cbor);
  ARMSTUDY_CHECK(rd.ok(), "a rendered part arrives whole");
  part.jd = nlohmann::ordered_json::from_cbor(cbor);
  part.md = rd.getString();
  part.images_md = rd.getString();
  for (auto n = rd.get<std::uint64_t>(); rd.ok() && n > 0; --n) {
    std::vector<std::string> row(rd.get<std::uint64_t>());
    for (std::string& c : row) c = rd.getString();
    part.rows.push_back(std::move(row));
  }
  for (auto n = rd.get<std::uint64_t>(); rd.ok() && n > 0; --n) files.push_back(rd.getString());
  ARMSTUDY_CHECK(rd.finished(), "a rendered part arrives whole");
}

std::vector<std::string> renderShared(const UnitRunner* runner, const std::string& id,
                                      std::size_t n, int threads,
                                      const std::function<std::string(std::size_t)>& render) {
  std::vector<std::string> parts(n);
  SharedLoop loop;
  loop.id = id;
  loop.items = static_cast<long>(n);
  loop.chunk = 1;
  loop.compute = [&](const std::vector<SharedLoop::Chunk>& mine) {
    // Items are independent (each its own files and bytes), so this process's share renders on
    // its threads as well.
    const std::vector<long> items = SharedLoop::itemsOf(mine);
    parallelFor(static_cast<int>(items.size()), threads, [&](int k) {
      const auto it = static_cast<std::size_t>(items[static_cast<std::size_t>(k)]);
      parts[it] = render(it);
    });
  };
  loop.pack = [&](std::size_t, const ItemRange& range) {
    UnitWriter b(kPartsMagic);
    for (long i = range.begin; i < range.end; ++i) b.putString(parts[static_cast<std::size_t>(i)]);
    return b.bytes();
  };
  loop.unpack = [&](std::size_t, const ItemRange& range, const std::string& bytes) {
    UnitReader rd(bytes, kPartsMagic);
    for (long i = range.begin; i < range.end; ++i)
      parts[static_cast<std::size_t>(i)] = rd.getString();
    ARMSTUDY_CHECK(rd.finished(), "rendered parts arrive whole");
  };
  runSharedLoop(runner, loop);
  return parts;
}

}  // namespace armstudy
