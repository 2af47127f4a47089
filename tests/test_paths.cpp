// The source folder and the armstudy program the tests were built with (test_support.hpp). Only
// this translation unit names them, so that the other test sources compile to the same objects
// wherever the work tree lies (a compiler cache shares them between clones).
#include <string>

namespace armstudy::test {

std::string sourceDir() { return ARMSTUDY_SOURCE_DIR; }
std::string binaryPath() { return ARMSTUDY_BINARY; }

}  // namespace armstudy::test
