// libFuzzer target: obj inputs (fuzz/fuzz_inputs.h, obj_input).
#include "fuzz/fuzz_inputs.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  sylva::fuzz::obj_input(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
