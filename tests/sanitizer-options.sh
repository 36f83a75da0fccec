# The sanitizers' options for the asan preset's tests and fuzz targets; sourced by .ci/run and
# scripts/run-fuzz from the repository root.
#
# Leaks inside Mesa (llvmpipe keeps JIT state alive at exit) and teem's error paths are not ours to fix
# (tests/lsan.supp); ours are still reported.
#
# intercept_tls_get_addr=0: clang 14's __tls_get_addr interceptor guesses that a dynamic TLS block
# starting 16 bytes into a page carries a pre-2.25 glibc header and reads its bounds from the two words
# before it. Since glibc 2.25 those blocks come from malloc, so now and then one of Mesa's lands there
# by chance; LeakSanitizer then scans a garbage range at exit and dies ("Tracer caught signal 11", a
# fatal error, not a leak: 2 runs in 150 of a DVT render test). Without the interceptor the thread's
# static TLS and its DTV are still scanned, so the blocks' pointers still count.
export LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0:intercept_tls_get_addr=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
