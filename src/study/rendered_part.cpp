#include "study/rendered_part.hpp"

#include <cstdint>
#include <string_view>

#include "common/errors.hpp"
#include "common/parallel_for.hpp"
#include "study/checkpoint.hpp"
#include "study/shared_loop.hpp"

namespace armstudy {

namespace {
constexpr std::string_view kPartMagic = "armstudy-rendered-part-2";
constexpr std::string_view kPartsMagic = "armstudy-rendered-parts-1";
void putStrings(UnitWriter& b, const std::vector<std::string>& v) {
  b.put<std::uint64_t>(v.size());
  for (const std::string& s : v) b.putString(s);
}

std::vector<std::string> getStrings(UnitReader& rd) {
  std::vector<std::string> v;
  for (auto n = rd.get<std::uint64_t>(); rd.ok() && n > 0; --n) v.push_back(rd.getString());
  return v;
}

// A document's blocks, each with every field of report::Block.
void putDocument(UnitWriter& b, const report::Document& doc) {
  b.put<std::uint64_t>(doc.blocks().size());
  for (const report::Block& k : doc.blocks()) {
    b.put<std::int32_t>(static_cast<std::int32_t>(k.kind));
    b.put<std::int32_t>(k.level);
    b.putString(k.text);
    b.put<std::uint64_t>(k.images.size());
    for (const report::FigureImage& im : k.images) {
      b.putString(im.alt);
      b.putString(im.path);
    }
    putStrings(b, k.header);
    b.put<std::uint64_t>(k.rows.size());
    for (const auto& row : k.rows) putStrings(b, row);
    b.put<std::int32_t>(static_cast<std::int32_t>(k.rule));
    putStrings(b, k.items);
  }
}

report::Document getDocument(UnitReader& rd) {
  std::vector<report::Block> blocks;
  for (auto n = rd.get<std::uint64_t>(); rd.ok() && n > 0; --n) {
    report::Block k;
    const auto kind = rd.get<std::int32_t>();
    ARMSTUDY_CHECK(kind >= 0 && kind <= static_cast<std::int32_t>(report::Block::Kind::markdown),
                   "a rendered part's blocks are of known kinds");
    k.kind = static_cast<report::Block::Kind>(kind);
    k.level = rd.get<std::int32_t>();
    k.text = rd.getString();
    for (auto m = rd.get<std::uint64_t>(); rd.ok() && m > 0; --m) {
      report::FigureImage im;
      im.alt = rd.getString();
      im.path = rd.getString();
      k.images.push_back(std::move(im));
    }
    k.header = getStrings(rd);
    for (auto m = rd.get<std::uint64_t>(); rd.ok() && m > 0; --m) k.rows.push_back(getStrings(rd));
    k.rule = static_cast<report::TableRule>(rd.get<std::int32_t>());
    k.items = getStrings(rd);
    blocks.push_back(std::move(k));
  }
  return report::Document(std::move(blocks));
}

}  // namespace

std::string packRenderedPart(const RenderedPart& part, const Writer& w) {
  UnitWriter b(kPartMagic);
  b.putVector(nlohmann::ordered_json::to_cbor(part.jd));
  putDocument(b, part.doc);
  putDocument(b, part.images);
  b.put<std::uint64_t>(part.rows.size());
  for (const auto& row : part.rows) putStrings(b, row);
  putStrings(b, w.files());
  return b.bytes();
}

void unpackRenderedPart(const std::string& bytes, RenderedPart& part,
                        std::vector<std::string>& files) {
  UnitReader rd(bytes, kPartMagic);
  std::vector<std::uint8_t> cbor;
  rd.getVector(cbor);
  ARMSTUDY_CHECK(rd.ok(), "a rendered part arrives whole");
  part.jd = nlohmann::ordered_json::from_cbor(cbor);
  part.doc = getDocument(rd);
  part.images = getDocument(rd);
  for (auto n = rd.get<std::uint64_t>(); rd.ok() && n > 0; --n) part.rows.push_back(getStrings(rd));
  for (std::string& f : getStrings(rd)) files.push_back(std::move(f));
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
