# Run at build time (cmake -P) by the gearmc_version_info target: writes the version source
# with the project version and the current git commit. configure_file only rewrites the output
# when its content changes, so an unchanged commit costs no recompilation.
#   -DSOURCE_DIR=... -DINPUT=version.cpp.in -DOUTPUT=... -DGEARMC_VERSION=x.y.z
set(GEARMC_GIT_HASH "unknown")
find_package(Git QUIET)
if(GIT_FOUND AND EXISTS "${SOURCE_DIR}/.git")
  execute_process(COMMAND "${GIT_EXECUTABLE}" -C "${SOURCE_DIR}" rev-parse --short=12 HEAD
                  OUTPUT_VARIABLE hash OUTPUT_STRIP_TRAILING_WHITESPACE
                  RESULT_VARIABLE failed ERROR_QUIET)
  if(NOT failed AND hash)
    set(GEARMC_GIT_HASH "${hash}")
    execute_process(COMMAND "${GIT_EXECUTABLE}" -C "${SOURCE_DIR}" diff --quiet HEAD --
                    RESULT_VARIABLE dirty ERROR_QUIET)
    if(dirty)
      set(GEARMC_GIT_HASH "${GEARMC_GIT_HASH}-dirty")
    endif()
  endif()
endif()
configure_file("${INPUT}" "${OUTPUT}" @ONLY)
