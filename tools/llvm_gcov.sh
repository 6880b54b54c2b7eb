#!/usr/bin/env bash
# gcov for lcov --gcov-tool in a clang build (setup.sh's coverage_capture): llvm-cov's gcov mode
# reads the notes and counts clang's --coverage writes (Debian's llvm-14).
exec llvm-cov-14 gcov "$@"
