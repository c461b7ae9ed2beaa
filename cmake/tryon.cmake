# Helpers shared by every folder's CMakeLists.txt.

pkg_check_modules(CMOCKA REQUIRED IMPORTED_TARGET cmocka)

# tryon_add_test(NAME <name> SOURCES <files...> LIBS <targets...> [TIMEOUT <s>] [LABELS <l...>])
# Builds a cmocka test executable and registers it with ctest. Every test gets
# a timeout so a hang fails the suite instead of stalling CI.
function(tryon_add_test)
  cmake_parse_arguments(T "" "NAME;TIMEOUT" "SOURCES;LIBS;LABELS;ENV" ${ARGN})
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 60)
  endif()
  add_executable(${T_NAME} ${T_SOURCES})
  target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} PkgConfig::CMOCKA m)
  add_test(NAME ${T_NAME} COMMAND ${T_NAME})
  set_tests_properties(${T_NAME} PROPERTIES TIMEOUT ${T_TIMEOUT})
  if(T_LABELS)
    set_tests_properties(${T_NAME} PROPERTIES LABELS "${T_LABELS}")
  endif()
  set(env ${T_ENV})
  if(TRYON_SANITIZE)
    # PoCL and LLVM keep memory until exit by design; tests/lsan.supp names only them.
    list(APPEND env
         "LSAN_OPTIONS=suppressions=${PROJECT_SOURCE_DIR}/tests/lsan.supp:print_suppressions=0"
         "UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1")
  endif()
  if(env)
    set_tests_properties(${T_NAME} PROPERTIES ENVIRONMENT "${env}")
  endif()
endfunction()

# tryon_add_fuzzer(NAME <name> SOURCES <files...> [LIBS <targets...>] [DEFS <defs...>])
# One libFuzzer harness (TRYON_FUZZ builds only). Its seed corpus is tests/fuzz/corpus/<name>/;
# tests/fuzz/run.sh runs every harness built. All harnesses build with the target fuzz_all.
function(tryon_add_fuzzer)
  if(NOT TRYON_FUZZ)
    return()
  endif()
  cmake_parse_arguments(F "" "NAME" "SOURCES;LIBS;DEFS" ${ARGN})
  add_executable(${F_NAME} ${F_SOURCES})
  target_link_libraries(${F_NAME} PRIVATE ${F_LIBS})
  target_link_options(${F_NAME} PRIVATE -fsanitize=fuzzer)
  if(F_DEFS)
    target_compile_definitions(${F_NAME} PRIVATE ${F_DEFS})
  endif()
  if(NOT TARGET fuzz_all)
    add_custom_target(fuzz_all)
  endif()
  add_dependencies(fuzz_all ${F_NAME})
endfunction()
