// ISOATLAS_CLONES("avx2", ...): the function is compiled for each named target and for the baseline,
// and the one the processor can run is chosen when the program loads (target_clones), so Debian's
// portable flags still get the wider instructions. Only on x86-64, and not under ThreadSanitizer:
// its runtime is not set up yet when the loader runs the clones' resolver, and the program crashes.
#pragma once

#if defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define ISOATLAS_THREAD_SANITIZER 1
#endif
#endif
#if defined(__SANITIZE_THREAD__) && !defined(ISOATLAS_THREAD_SANITIZER)
#define ISOATLAS_THREAD_SANITIZER 1
#endif

#if defined(__x86_64__) && !defined(ISOATLAS_THREAD_SANITIZER)
#define ISOATLAS_CLONES(...) __attribute__((target_clones(__VA_ARGS__, "default")))
#else
#define ISOATLAS_CLONES(...)
#endif
