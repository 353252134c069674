# Helpers that give every slicecap target the same language level and warnings.

function(slicecap_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow)
  if(SLICECAP_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# slicecap_module(NAME SOURCES ... DEPENDS ...): one static library per module under lib/NAME,
# public headers in lib/NAME/include/slicecap/NAME/, target slicecap::NAME.
function(slicecap_module name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPENDS;PRIVATE_DEPENDS" ${ARGN})
  add_library(slicecap_${name} STATIC ${ARG_SOURCES})
  add_library(slicecap::${name} ALIAS slicecap_${name})
  target_include_directories(slicecap_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_compile_features(slicecap_${name} PUBLIC cxx_std_20)
  target_link_libraries(slicecap_${name} PUBLIC ${ARG_DEPENDS} PRIVATE ${ARG_PRIVATE_DEPENDS})
  set_target_properties(slicecap_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  slicecap_warnings(slicecap_${name})
endfunction()

# slicecap_test(NAME SOURCES ... DEPENDS ...): a GoogleTest binary registered with ctest.
function(slicecap_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPENDS;LABELS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPENDS} GTest::gtest_main GTest::gmock)
  target_compile_definitions(${name} PRIVATE
    SLICECAP_SHARED_DATA_DIR="${SLICECAP_SHARED_DATA_DIR}"
    SLICECAP_TEST_TMP_DIR="${SLICECAP_TEST_TMP_DIR}")
  slicecap_warnings(${name})
  if(NOT ARG_LABELS)
    set(ARG_LABELS unit)
  endif()
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "${ARG_LABELS}")
endfunction()
