# pnc_library(<name> SOURCES ... DEPS ...): one library per top-level folder, public headers
# in <folder>/include/pnc/<name>/, warnings on.
function(pnc_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                           -Wno-sign-conversion)
endfunction()

function(pnc_library name)
  cmake_parse_arguments(ARG "SHARED" "" "SOURCES;DEPS;PRIVATE_DEPS" ${ARGN})
  if(ARG_SHARED)
    add_library(pnc_${name} SHARED ${ARG_SOURCES})
  else()
    add_library(pnc_${name} STATIC ${ARG_SOURCES})
  endif()
  add_library(pnc::${name} ALIAS pnc_${name})
  target_include_directories(pnc_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_link_libraries(pnc_${name} PUBLIC ${ARG_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  pnc_warnings(pnc_${name})
endfunction()
