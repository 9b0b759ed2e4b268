# One warning list for every target of the project (see rtuscope_apply_warnings).
set(RTUSCOPE_WARNINGS
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wsign-conversion
  -Wnon-virtual-dtor -Wold-style-cast -Wcast-align -Woverloaded-virtual
  -Wnull-dereference -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)
if(RTUSCOPE_WERROR)
  list(APPEND RTUSCOPE_WARNINGS -Werror)
endif()

function(rtuscope_apply_warnings target)
  target_compile_options(${target} PRIVATE ${RTUSCOPE_WARNINGS})
endfunction()
