#pragma once
// Output rendered by the process that owns it (docs/distributed.md "Files"): a loop shared among
// the processes of a run renders pieces of a stage's output (a design's files and figures, a
// pair's images) on each process's threads; the owner writes the files into the study's output
// folder itself, and only a part travels: the piece's summary entry, report blocks, table rows and
// the names of the files it wrote. Every process then joins the parts in item order, so the files
// and their order are those of a single process.
#include <cstddef>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "report/document.hpp"
#include "study/writer.hpp"

namespace armstudy {

class UnitRunner;

struct RenderedPart {
  nlohmann::ordered_json jd;                   // the piece's summary entry (null: none)
  report::Document doc, images;                // report blocks: the text, the figures
  std::vector<std::vector<std::string>> rows;  // table rows
};

// The part and the names of the files `w` lists, as bytes (the entry as CBOR).
std::string packRenderedPart(const RenderedPart& part, const Writer& w);
// The inverse: fills `part` and appends the files' names (relative to the output folder) to
// `files`, in the order they were written.
void unpackRenderedPart(const std::string& bytes, RenderedPart& part,
                        std::vector<std::string>& files);

// Renders items [0, n) in a loop shared among the runner's processes (id `id`, one item per
// chunk), each process its items on `threads` threads: render(i) writes item i's files and returns
// its packed part. Returns every item's bytes, on every process.
std::vector<std::string> renderShared(const UnitRunner* runner, const std::string& id,
                                      std::size_t n, int threads,
                                      const std::function<std::string(std::size_t)>& render);

}  // namespace armstudy
