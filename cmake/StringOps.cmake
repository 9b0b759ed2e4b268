# How GCC copies and clears fixed-size blocks on x86-64. Its generic tuning turns a known-size
# copy or clear of 128 bytes or more (a Record, a DataAccess, a decoded PDU) into `rep movs` /
# `rep stos`, whose start-up costs tens of cycles: on the hot path of a replay those
# instructions took most of the samples of the functions they were in (perf annotate). Up to
# 512 bytes an unrolled loop of moves does the same work without the start-up; longer blocks
# still go to the library. Measured on 5 M frames (tools/bench/t.sh, min of 4): report from the
# native pcapng 1.35 -> 1.28 s, from USB hex 2.03 -> 1.71 s, from per-byte hex 3.80 -> 3.59 s.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64")
  add_compile_options(-mmemset-strategy=unrolled_loop:512:noalign,libcall:-1:noalign
                      -mmemcpy-strategy=unrolled_loop:512:noalign,libcall:-1:noalign)
endif()
