# cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DCONSUMER_DIR=... -P install_test.cmake
# Installs the build into WORK_DIR/prefix and uses it as an outside user would.
cmake_minimum_required(VERSION 3.25)

function(run)
  cmake_parse_arguments(R "" "OUTPUT;ERROR" "COMMAND;ENV" ${ARGN})
  execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=RICOCHET_DATA_DIR
                          --unset=RICOCHET_LIGGGHTS_INPUTS ${R_ENV} ${R_COMMAND}
                  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  list(JOIN R_COMMAND " " shown)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "failed (${status}): ${shown}\n${out}\n${err}")
  endif()
  message(STATUS "ok: ${shown}")
  if(R_OUTPUT)
    set(${R_OUTPUT} "${out}" PARENT_SCOPE)
  endif()
endfunction()

function(expect text what)
  string(FIND "${text}" "${what}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "expected '${what}' in:\n${text}")
  endif()
endfunction()

set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${WORK_DIR})

# 1. Install.
run(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(f bin/ricochet lib/cmake/Ricochet/RicochetConfig.cmake
          lib/cmake/Ricochet/RicochetConfigVersion.cmake include/ricochet/effects/effect.hpp
          share/ricochet/data/lab/cylinders.csv share/ricochet/liggghts-inputs/bed/in.bed)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()

# 2. No path of the source tree compiled into what was installed (data are found at run time).
string(REGEX REPLACE "([][+.*()^$?|\\])" "\\\\\\1" source_re "${SOURCE_DIR}/")
file(GLOB_RECURSE binaries ${prefix}/bin/* ${prefix}/lib/*.a)
foreach(b IN LISTS binaries)
  file(STRINGS ${b} hits REGEX "${source_re}")
  if(hits)
    message(FATAL_ERROR "${b} holds source paths: ${hits}")
  endif()
endforeach()

# 3. The plugin example, configured against the installed package only.
run(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/user-effect -B ${WORK_DIR}/plugin
            -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix})
run(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/plugin)
set(plugin ${WORK_DIR}/plugin/libgrazing_restitution.so)

# 4. Loaded as docs/tutorial-effect.md says, by the installed program.
run(COMMAND ${prefix}/bin/ricochet effects grazing_restitution --plugin ${plugin} --json
    OUTPUT out)
expect("${out}" "\"grazing_restitution\"")
run(COMMAND ${prefix}/bin/ricochet simulate --vin 2.9,-2.3,-65 --plugin ${plugin}
            --add grazing_restitution --set kg=1 --json OUTPUT out)
expect("${out}" "\"vout\"")

# 5. The installed program finds the installed data (synth resamples the lab's incident states
# from share/ricochet/data), with no environment variable set.
run(COMMAND ${prefix}/bin/ricochet synth --n 5 --out ${WORK_DIR}/synth.csv)

# 6. A program linking the installed libraries (find_package(Ricochet), Ricochet::diagnosis).
run(COMMAND ${CMAKE_COMMAND} -S ${CONSUMER_DIR} -B ${WORK_DIR}/consumer
            -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix})
run(COMMAND ${CMAKE_COMMAND} --build ${WORK_DIR}/consumer)
run(COMMAND ${WORK_DIR}/consumer/consumer OUTPUT out
    ENV RICOCHET_DATA_DIR=${prefix}/share/ricochet/data)
expect("${out}" "28 lab releases from ${prefix}/share/ricochet/data")
