/* vergence — fuzz targets. Each file defines LLVMFuzzerTestOneInput; built
 * with clang and -fsanitize=fuzzer (VG_FUZZ=ON) it is a libFuzzer target,
 * otherwise fuzz_main.c replays files and folders of inputs through it (the
 * regression inputs under tests/fuzz/regressions/<target>/ run as tests in
 * every build). A target must never crash, leak or hang on any input. */
#pragma once
#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
