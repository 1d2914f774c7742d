# Warnings are errors for the project's own code (TEXSIM_WERROR=OFF to relax locally).
option(TEXSIM_WERROR "Treat warnings as errors" ON)
function(texsim_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
    -Wno-sign-conversion -Wnon-virtual-dtor -Wold-style-cast -Woverloaded-virtual)
  if(TEXSIM_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
