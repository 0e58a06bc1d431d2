# Installs the build tree into WORK_DIR/prefix, then, from that prefix only:
# configures, builds and runs the consumer projects in CONSUMER_DIR (C and
# Fortran, find_package), builds the C consumer again through pkg-config,
# and runs the installed CLI (--version, a small build with its picture).
file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix}
                RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "install failed")
endif()

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  message(STATUS "${what}: ${out}")
  set(output "${out}" PARENT_SCOPE)
endfunction()

# A sanitizer build of the library needs the consumers built with the same flags.
string(REPLACE ";" " " flags "${CONSUMER_FLAGS}")
run("consumer configure" ${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${WORK_DIR}/build
    -DCMAKE_PREFIX_PATH=${prefix} -DWITH_FORTRAN=${WITH_FORTRAN} "-DCMAKE_C_FLAGS=${flags}" "-DCMAKE_Fortran_FLAGS=${flags}"
    "-DCMAKE_EXE_LINKER_FLAGS=${flags}")
run("consumer build" ${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run("C consumer" ${WORK_DIR}/build/consumer)
if(WITH_FORTRAN)
  run("Fortran consumer" ${WORK_DIR}/build/consumer_fortran)
endif()

# pkg-config, from the installed .pc files (relocatable: found from their place).
file(GLOB pc_dir LIST_DIRECTORIES true ${prefix}/lib*/pkgconfig ${prefix}/lib/*/pkgconfig)
set(ENV{PKG_CONFIG_PATH} "${pc_dir}")
run("pkg-config" pkg-config --cflags --libs unimesh)
string(STRIP "${output}" pc_flags)
separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
get_filename_component(libdir ${pc_dir} DIRECTORY)
run("pkg-config C build" cc ${CONSUMER_FLAGS} ${CONSUMER_DIR}/consumer.c ${pc_flags} -Wl,-rpath,${libdir}
    -o ${WORK_DIR}/consumer_pc)
run("pkg-config C consumer" ${WORK_DIR}/consumer_pc)
if(WITH_FORTRAN)
  run("pkg-config fortran" pkg-config --cflags --libs unimesh-fortran)
  string(STRIP "${output}" pc_flags)
  separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
  run("pkg-config Fortran build" gfortran ${CONSUMER_FLAGS} ${CONSUMER_DIR}/consumer.F90 ${pc_flags}
      -Wl,-rpath,${libdir} -J ${WORK_DIR} -o ${WORK_DIR}/consumer_fortran_pc)
  run("pkg-config Fortran consumer" ${WORK_DIR}/consumer_fortran_pc)
endif()

# The CLI from the prefix: it finds its library and its plotting script there.
run("CLI --version" ${prefix}/bin/unimesh --version)
run("CLI build" ${prefix}/bin/unimesh build --spacing-km 2000 --threads 1 --out ${WORK_DIR}/out)
if(NOT EXISTS ${WORK_DIR}/out/mesh.nc)
  message(FATAL_ERROR "the installed CLI wrote no mesh.nc")
endif()
execute_process(COMMAND /usr/bin/python3 -c "import matplotlib" RESULT_VARIABLE no_matplotlib
                OUTPUT_QUIET ERROR_QUIET)
if(no_matplotlib EQUAL 0 AND NOT EXISTS ${WORK_DIR}/out/quality.png)
  message(FATAL_ERROR "the installed CLI drew no quality.png (its plotting script not found?)")
endif()
