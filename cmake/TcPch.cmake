# Precompiled headers (docs/choices.md, "Precompiled headers and gold for the build from scratch"): the
# external headers nearly every translation unit includes (the standard library, fmt, PETSc,
# Eigen, GoogleTest) are parsed once per group of targets compiled with the same flags, not once
# per file. A group is the targets that compile identically: the static libraries (-fPIC) and
# the executables (not PIC) must not share one. TC_PCH=OFF builds without them, which also
# checks that every file includes what it uses.
# Off by default under ccache: ccache does not cache a compile that uses a precompiled header
# (without sloppiness settings), and a shared cache saves more than the headers do.
if(CMAKE_CXX_COMPILER_LAUNCHER MATCHES "ccache")
  set(tc_pch_default OFF)
else()
  set(tc_pch_default ON)
endif()
option(TC_PCH "Precompile the common external headers (build time from scratch)" ${tc_pch_default})

set(TC_PCH_STD <algorithm> <array> <chrono> <cmath> <cstring> <filesystem> <fstream>
               <functional> <limits> <map> <memory> <optional> <set> <span> <sstream> <string>
               <string_view> <utility> <vector>)

# tc_precompile(TARGET HEADERS ...): TARGET compiles the listed headers once for itself.
function(tc_precompile target)
  if(TC_PCH)
    target_precompile_headers(${target} PRIVATE ${ARGN})
  endif()
endfunction()

# tc_reuse_precompiled(TARGET FROM): TARGET uses FROM's precompiled headers (same flags; CMake
# then builds FROM first).
function(tc_reuse_precompiled target from)
  if(TC_PCH)
    target_precompile_headers(${target} REUSE_FROM ${from})
  endif()
endfunction()
