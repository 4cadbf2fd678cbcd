// libFuzzer target: exr inputs (fuzz/fuzz_inputs.h, exr_input).
#include "fuzz/fuzz_inputs.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  sylva::fuzz::exr_input(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
