// One libFuzzer binary per reader: compiled with
// -DARMSTUDY_FUZZ_TARGET=<design|study|csv|baseline|urdf|urdf_mesh> and
// -fsanitize=fuzzer,address,undefined (CMake option ARMSTUDY_FUZZ, clang; README "Fuzzing").
#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  armstudy::fuzz::ARMSTUDY_FUZZ_TARGET(data, size);
  return 0;
}
