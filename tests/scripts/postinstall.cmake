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

# The Python package, pip-installed from a copy of bindings/python (pip
# builds in the tree it is given) into a scratch site, its tests run against
# it and the installed library (found by the loader: no UNIMESH_LIBRARY).
if(PYTHON AND PYTHON_SOURCE_DIR)
  file(COPY ${PYTHON_SOURCE_DIR}/ DESTINATION ${WORK_DIR}/python_source PATTERN __pycache__ EXCLUDE)
  run("pip install" ${PYTHON} -m pip install --quiet --no-index --no-build-isolation --no-deps
      --target ${WORK_DIR}/site ${WORK_DIR}/python_source)
  set(ENV{PYTHONPATH} ${WORK_DIR}/site)
  set(ENV{PYTHONDONTWRITEBYTECODE} 1)
  set(ENV{LD_LIBRARY_PATH} ${libdir})
  unset(ENV{UNIMESH_LIBRARY})
  run("installed Python package" ${PYTHON} -c
      "import sys, unimesh\nassert unimesh.__file__.startswith(sys.argv[1]), unimesh.__file__\nprint(unimesh.__file__, unimesh.version())"
      ${WORK_DIR}/site)
  execute_process(COMMAND ${PYTHON} -m unittest test_mesh test_triangulation
                  WORKING_DIRECTORY ${PYTHON_SOURCE_DIR}/tests RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "the binding's tests against the installed package failed:\n${err}")
  endif()
endif()

# The CLI from the prefix: it finds its library and its plotting scripts there.
run("CLI --version" ${prefix}/bin/unimesh --version)
run("CLI build" ${prefix}/bin/unimesh build --spacing-km 2000 --threads 1 --out ${WORK_DIR}/out)
if(NOT EXISTS ${WORK_DIR}/out/mesh.nc)
  message(FATAL_ERROR "the installed CLI wrote no mesh.nc")
endif()
execute_process(COMMAND /usr/bin/python3 -c "import matplotlib, netCDF4, numpy" RESULT_VARIABLE no_matplotlib
                OUTPUT_QUIET ERROR_QUIET)
foreach(picture quality.png mesh.png)
  if(no_matplotlib EQUAL 0 AND NOT EXISTS ${WORK_DIR}/out/${picture})
    message(FATAL_ERROR "the installed CLI drew no ${picture} (its plotting script not found?)")
  endif()
endforeach()
