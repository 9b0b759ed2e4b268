# ASan + UBSan for the whole build, so tests exercise every module instrumented.
if(RTUSCOPE_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
if(RTUSCOPE_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "RTUSCOPE_FUZZ needs clang (CXX=clang++)")
  endif()
  # A UBSan finding must stop the run like an ASan one: libFuzzer then saves the input as a
  # reproducer. Recoverable, it only prints and the run goes on with nothing saved.
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all
                      -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
