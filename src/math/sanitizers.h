// Which sanitizer this translation unit is built with, in one spelling for both compilers: GCC
// defines __SANITIZE_ADDRESS__ / __SANITIZE_THREAD__, clang 14 only answers
// __has_feature(address_sanitizer) / __has_feature(thread_sanitizer).
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define ANAMORPH_ASAN 1
#endif
#if defined(__SANITIZE_THREAD__)
#define ANAMORPH_TSAN 1
#endif
#if defined(__has_feature)
#if __has_feature(address_sanitizer) && !defined(ANAMORPH_ASAN)
#define ANAMORPH_ASAN 1
#endif
#if __has_feature(thread_sanitizer) && !defined(ANAMORPH_TSAN)
#define ANAMORPH_TSAN 1
#endif
#endif
