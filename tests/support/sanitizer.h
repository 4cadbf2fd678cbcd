#pragma once
// Whether this build is instrumented by AddressSanitizer (-DSYLVA_SANITIZE=ON, or the fuzz build with
// tests). A test that cannot run under it skips with the reason, in that build only: ASan reserves
// terabytes of shadow address space at start-up, so a process cannot start under an address-space
// limit (`ulimit -v`).

namespace sylva::test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kAddressSanitizer = true;
#else
inline constexpr bool kAddressSanitizer = false;
#endif
#else
inline constexpr bool kAddressSanitizer = false;
#endif

}  // namespace sylva::test
