# The web decoder's tests (issue 28), included by tests/CMakeLists.txt. Whole-system tests
# (emscripten, node, npm, a browser): LABELS integration. Web.Build compiles the decoder with
# web/build.sh into build/web (a fixture: the tests that need it run after it).
find_program(PM_NODE node PATHS /usr/bin NO_DEFAULT_PATH)
set(PM_WEB_BUILD ${PROJECT_BINARY_DIR}/web)
add_test(NAME Web.Build COMMAND bash ${PROJECT_SOURCE_DIR}/web/build.sh ${PM_WEB_BUILD})
set_tests_properties(Web.Build PROPERTIES FIXTURES_SETUP pm_web TIMEOUT 1200 LABELS integration)

set(PM_WEB_ENV
  PM_WEB_DIST=${PM_WEB_BUILD}/dist
  PM_WEB_WORK=${PM_WEB_BUILD}/work
  PM_SOURCE_DIR=${PROJECT_SOURCE_DIR}
  PM_SHARED_MESHES_DIR=${PROJECT_SOURCE_DIR}/../shared/meshes
  PMDEC=$<TARGET_FILE:pmdec>
  PMENC=$<TARGET_FILE:pmenc>
  PM_MAKE_SAMPLES=$<TARGET_FILE:pm_make_samples>)
foreach(name levels streaming)
  add_test(NAME Web.${name}
           COMMAND ${PM_NODE} --test --test-reporter=spec ${PROJECT_SOURCE_DIR}/web/tests/${name}.test.mjs)
  set_tests_properties(Web.${name} PROPERTIES FIXTURES_REQUIRED pm_web RESOURCE_LOCK pm_web_work
                       ENVIRONMENT "${PM_WEB_ENV}" TIMEOUT 900 LABELS integration)
endforeach()
add_test(NAME Web.browser
         COMMAND ${PM_NODE} --test --test-reporter=spec ${PROJECT_SOURCE_DIR}/web/tests/browser.test.mjs)
set_tests_properties(Web.browser PROPERTIES FIXTURES_REQUIRED pm_web RESOURCE_LOCK pm_web_work
                     ENVIRONMENT "${PM_WEB_ENV}" TIMEOUT 900 LABELS integration)

# The TypeScript declarations (pm.d.ts, pm-core.d.ts) as a program that uses both entries
# meets them: tsc --strict compiles tests/types.check.ts without emitting anything
# (tests/tsconfig.types.json; tsc: Debian's node-typescript, from .ci/deps; about 5 s of CPU).
add_test(NAME Web.types COMMAND tsc -p tests/tsconfig.types.json
         WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}/web)
set_tests_properties(Web.types PROPERTIES TIMEOUT 300 LABELS integration)
