# Shared helpers for Marvin's targets: warnings, sanitizers, tests and benchmarks.

set(MARVIN_WARNINGS -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
    -Wnon-virtual-dtor -Wold-style-cast -Woverloaded-virtual)
set(MARVIN_C_WARNINGS -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion)

if(MARVIN_SANITIZE)
  add_compile_options(-fsanitize=${MARVIN_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${MARVIN_SANITIZE})
  if(MARVIN_SANITIZE MATCHES "thread" AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    # GCC warns that TSan does not model std::atomic_thread_fence (used by Boost.Asio);
    # the warning is about the tool, not our code, and would stop -Werror builds.
    add_compile_options(-Wno-tsan)
  endif()
endif()

if(CMAKE_UNITY_BUILD AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  # A unity build (scripts/build turns it on: it halves compile time) includes each .cpp
  # into a generated one, so GCC takes our sources for headers and warns when a class
  # defined there uses a type from the file's anonymous namespace. Only headers need that
  # warning; a header of ours that did it would still be caught by normal builds.
  add_compile_options($<$<COMPILE_LANGUAGE:CXX>:-Wno-subobject-linkage>)
endif()

# marvin_target_defaults(TARGET): our warning set (errors under MARVIN_WERROR).
function(marvin_target_defaults target)
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "INTERFACE_LIBRARY")
    return()
  endif()
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CXX>:${MARVIN_WARNINGS}>
    $<$<COMPILE_LANGUAGE:C>:${MARVIN_C_WARNINGS}>
    $<$<BOOL:${MARVIN_WERROR}>:-Werror>)
endfunction()

# marvin_add_library(NAME SOURCES... [DEPS libs...]): a static library of ours.
function(marvin_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_library(${name} STATIC ${ARG_SOURCES})
  target_link_libraries(${name} PUBLIC ${ARG_DEPS})
  marvin_target_defaults(${name})
endfunction()

# marvin_add_test(NAME SOURCES... [DEPS libs...] [LABELS labels...] [TIMEOUT s])
# A doctest executable registered with CTest. Label `long` tests only exist with
# MARVIN_LONG_TESTS=ON; label `tsan` also runs under ThreadSanitizer in CI; label `nosan`
# is skipped under the sanitizers (e.g. tests that fork toolchains), so a sanitizer build
# does not even compile it. Check with if(TARGET ...) before adding to a test that may not exist.
function(marvin_add_test name)
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;DEPS;LABELS" ${ARGN})
  if("long" IN_LIST ARG_LABELS AND NOT MARVIN_LONG_TESTS)
    return()
  endif()
  if("nosan" IN_LIST ARG_LABELS AND MARVIN_SANITIZE)
    return()
  endif()
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE marvin_doctest_main ${ARG_DEPS})
  marvin_target_defaults(${name})
  add_test(NAME ${name} COMMAND ${name})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  set_tests_properties(${name} PROPERTIES TIMEOUT ${ARG_TIMEOUT} LABELS "${ARG_LABELS}"
                       ENVIRONMENT "MARVIN_SOURCE_DIR=${PROJECT_SOURCE_DIR};MARVIN_BUILD_DIR=${PROJECT_BINARY_DIR}")
  if("tsan" IN_LIST ARG_LABELS)
    if(NOT TARGET marvin_tsan_tests)
      add_custom_target(marvin_tsan_tests)
    endif()
    add_dependencies(marvin_tsan_tests ${name})
  endif()
endfunction()

# marvin_add_bench(NAME SOURCES... [DEPS libs...]): a benchmark program (prints figures,
# never fails on time). Built with everything; run by hand: build/benchmarks/NAME.
function(marvin_add_bench name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS})
  marvin_target_defaults(${name})
  set_target_properties(${name} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/benchmarks)
endfunction()
