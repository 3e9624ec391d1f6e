# The package test (ctest "package_consumer"): installs this build into a fresh prefix, then
# configures and builds two projects against it with find_package(gearmc):
# - tests/package/consumer, checking what it prints (the version line and 90.21 mm, see
#   consumer.cpp);
# - examples/run_scenario (the C++ API example of docs/api.md), run on scenarios/p1_reference.yaml
#   with 20 gears; its statistics must equal those of summary.json from the installed
#   `gearmc run` with the same scenario and gear count (compare_example.py);
# and checks that only the public headers and the headers they include are installed.
# Arguments: -DBUILD_DIR= -DSOURCE_DIR= -DWORK_DIR= -DVERSION= -DPYTHON= -DFLAGS= (compile and
# link flags of the consumers, e.g. the sanitizer options of a GEARMC_SANITIZE build).
file(REMOVE_RECURSE ${WORK_DIR})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGN}\n${out}")
  endif()
  set(output "${out}" PARENT_SCOPE)
endfunction()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/consumer -B ${WORK_DIR}/build -G Ninja
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix
    "-DCMAKE_CXX_FLAGS=${FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${FLAGS}")
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/consumer)
if(NOT output MATCHES "^gearmc ${VERSION} \\(git [^)]+\\)\nbase diameter 90\\.21 mm\n$")
  message(FATAL_ERROR "unexpected consumer output:\n${output}")
endif()
message(STATUS "consumer: ${output}")

# The C++ API example against the installed package, and the same run by the installed gearmc.
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/run_scenario -B ${WORK_DIR}/example -G Ninja
    -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix
    "-DCMAKE_CXX_FLAGS=${FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${FLAGS}")
run(${CMAKE_COMMAND} --build ${WORK_DIR}/example)
run(${WORK_DIR}/example/run_scenario ${SOURCE_DIR}/scenarios/p1_reference.yaml 20)
file(WRITE ${WORK_DIR}/example_output.txt "${output}")
message(STATUS "example: ${output}")
run(${WORK_DIR}/prefix/bin/gearmc run ${SOURCE_DIR}/scenarios/p1_reference.yaml --gears 20
    --quiet --out ${WORK_DIR}/run)
run(${PYTHON} ${SOURCE_DIR}/tests/package/compare_example.py ${WORK_DIR}/example_output.txt
    ${WORK_DIR}/run/summary.json)
message(STATUS "${output}")

# Installed headers: the public ones (marked "Public API") and what they include, nothing else.
file(GLOB_RECURSE installed RELATIVE ${WORK_DIR}/prefix/include ${WORK_DIR}/prefix/include/*.h)
if(EXISTS ${WORK_DIR}/prefix/include/engine/cli)
  message(FATAL_ERROR "the command line's headers are installed")
endif()
set(public_count 0)
foreach(header IN LISTS installed)
  file(STRINGS ${WORK_DIR}/prefix/include/${header} marker REGEX "^// Public API" LIMIT_COUNT 1)
  if(marker)
    math(EXPR public_count "${public_count} + 1")
  endif()
endforeach()
if(public_count LESS 5)
  message(FATAL_ERROR "only ${public_count} public headers installed: ${installed}")
endif()
list(LENGTH installed installed_count)
message(STATUS "installed headers: ${installed_count}, of them public: ${public_count}")
