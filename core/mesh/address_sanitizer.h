// Whether this translation unit is built with AddressSanitizer, for gcc
// (__SANITIZE_ADDRESS__) and clang (__has_feature) alike. Such a process reserves terabytes
// of shadow address space (no RLIMIT_AS can hold it) and runs several times slower.
#pragma once

namespace spheremap {

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

}  // namespace spheremap
