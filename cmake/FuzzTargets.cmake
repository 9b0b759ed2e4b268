# rtuscope_add_fuzz_target(name source corpus_dir)
#
# One fuzz target per parser stage, each a file defining LLVMFuzzerTestOneInput.
# - RTUSCOPE_FUZZ=ON (preset "fuzz"; Debian package clang): linked with libFuzzer; run by hand:
#   build-fuzz/tests/fuzz/<name> -max_total_time=300 <scratch dir> <corpus_dir>
# - otherwise: linked with a standalone driver, and CTest replays every file of the committed
#   corpus (seeds and named regressions) through it, under the build's sanitizers.
function(rtuscope_add_fuzz_target name source corpus_dir)
  if(RTUSCOPE_FUZZ)
    add_executable(${name} ${source})
    target_link_options(${name} PRIVATE -fsanitize=fuzzer)
  else()
    add_executable(${name} ${source} ${PROJECT_SOURCE_DIR}/tests/fuzz/standalone_driver.cpp)
    add_test(NAME fuzz_replay.${name} COMMAND ${name} ${corpus_dir})
  endif()
  target_link_libraries(${name} PRIVATE rtuscope_lib)
  rtuscope_apply_warnings(${name})
endfunction()
