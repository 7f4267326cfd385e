# install.stage: a fresh `cmake --install` of the build tree into STAGE (the fixture of the
# other install.* tests, which copy it elsewhere before using it).
file(REMOVE_RECURSE "${STAGE}")
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD}" --prefix "${STAGE}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install ${BUILD} --prefix ${STAGE} failed (${rc}):\n${out}${err}")
endif()
string(REGEX MATCHALL "-- Installing: " n "${out}")
list(LENGTH n n)
message(STATUS "installed ${n} files into ${STAGE}")
