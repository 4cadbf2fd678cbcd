// libFuzzer target: ply inputs (fuzz/fuzz_inputs.h, ply_input).
#include "fuzz/fuzz_inputs.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  sylva::fuzz::ply_input(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
