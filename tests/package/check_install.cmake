# The package test (ctest "package_consumer"): installs this build into a fresh prefix, then
# configures and builds tests/package/consumer against it with find_package(gearmc), runs the
# consumer and checks what it prints (the version line and 90.21 mm, see consumer.cpp).
# Arguments: -DBUILD_DIR= -DSOURCE_DIR= -DWORK_DIR= -DVERSION= -DFLAGS= (compile and link
# flags of the consumer, e.g. the sanitizer options of a GEARMC_SANITIZE build).
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
