// libFuzzer target: species files (fuzz/fuzz_inputs.h, species_input).
#include "fuzz/fuzz_inputs.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  sylva::fuzz::species_input(std::string_view(reinterpret_cast<const char*>(data), size), SYLVA_SOURCE_DIR);
  return 0;
}
