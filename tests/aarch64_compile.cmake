# The portable path builds for AArch64: the kernel sources (for the portable
# path, as core/CMakeLists.txt builds them) and the shipped shaders through
# the SDK, compiled with Debian's aarch64 cross compiler. GLM is header-only
# and the same for every architecture; nothing else they include is
# host-specific.
#
#   cmake -DCXX=aarch64-linux-gnu-g++ -DSOURCE=<facet> -DOUT=<dir> -P aarch64_compile.cmake
cmake_minimum_required(VERSION 3.25)
foreach(var CXX SOURCE OUT)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "aarch64_compile.cmake: -D${var}=... is required")
  endif()
endforeach()
file(MAKE_DIRECTORY "${OUT}/include")
file(CREATE_LINK /usr/include/glm "${OUT}/include/glm" SYMBOLIC)
set(common -std=c++20 -O2 -Wall -Wextra -Werror -Wno-psabi -fPIC -I${SOURCE}/plugins/include
           -isystem ${OUT}/include)
file(GLOB shaders "${SOURCE}/shaders/*/*.cpp")
set(kernels pipeline/kernels pipeline/rasterize pipeline/fragment pipeline/pixels pipeline/ao_kernels)
foreach(file IN LISTS kernels shaders)
  if(file IN_LIST kernels)
    set(src "${SOURCE}/core/src/${file}.cpp")
    set(flags -DFACET_KERNEL_NS=isa_portable -DFACET_KERNEL_TABLE=facet_kernels_portable
              -DFACET_KERNEL_ISA=portable -I${SOURCE}/core/include -I${SOURCE}/core/src)
  else()
    set(src "${file}")
    set(flags "")
  endif()
  get_filename_component(name "${src}" NAME_WE)
  execute_process(COMMAND "${CXX}" ${common} ${flags} -c "${src}" -o "${OUT}/${name}.o"
                  RESULT_VARIABLE status ERROR_VARIABLE errors)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "${src} does not build for AArch64:\n${errors}")
  endif()
endforeach()
