# One warning list for every target of the project (see rtuscope_apply_warnings).
set(RTUSCOPE_WARNINGS
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion
  -Wnon-virtual-dtor -Wold-style-cast -Wcast-align -Woverloaded-virtual
  -Wnull-dereference -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)
# At -O2 and above GCC 12 reports "potential null pointer dereference" inside Boost.Asio's
# scheduler and toml++'s node accessors once they are inlined into our code: paths that
# cannot be taken, in code that is not ours. The Release build (the quick start's) leaves the
# check out; the -O1 build that CI runs with -Werror keeps it for everything of ours.
list(APPEND RTUSCOPE_WARNINGS $<$<CONFIG:Release>:-Wno-null-dereference>)
if(RTUSCOPE_WERROR)
  list(APPEND RTUSCOPE_WARNINGS -Werror)
endif()

function(rtuscope_apply_warnings target)
  target_compile_options(${target} PRIVATE ${RTUSCOPE_WARNINGS})
endfunction()
