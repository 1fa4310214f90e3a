# Reliability tests (issue #5): randomized images with fixed seeds, checked against every guarantee or a
# documented exception, and resource safety (vertex cap, abort latency, determinism, thread independence).
# The libFuzzer target lives apart in fuzz/ (clang only); scripts/test-sanitizers.sh runs this whole suite
# under AddressSanitizer and UndefinedBehaviorSanitizer.

add_executable(DelaunayImageToMeshRandomizedGTests
  DelaunayImageToMeshRandomizedGTest.cxx
  DelaunayImageToMeshRandomizedResourceGTest.cxx
  DelaunayImageToMeshRandomizedRegressionGTest.cxx
)
target_link_libraries(DelaunayImageToMeshRandomizedGTests PRIVATE
  DelaunayImageToMesh ${ITK_LIBRARIES} GTest::gtest GTest::gtest_main)
# The checks decide orientations with CGAL's exact predicates, as the mesher does.
find_package(CGAL 5.5 REQUIRED)
find_package(Threads REQUIRED)
target_link_libraries(DelaunayImageToMeshRandomizedGTests PRIVATE CGAL::CGAL Threads::Threads)
# Each family of random cases is one test, so that CTest spreads them over the cores.
gtest_discover_tests(DelaunayImageToMeshRandomizedGTests DISCOVERY_TIMEOUT 120 PROPERTIES TIMEOUT 900 LABELS reliability)

# Every deliberate bug of scripts/mutation-check.sh must still apply to the source: a mutation whose text drifted
# would stop the check instead of testing the suite.
add_test(NAME DelaunayImageToMeshMutationCheck.EveryMutationApplies
  COMMAND bash ${PROJECT_SOURCE_DIR}/scripts/mutation-check.sh --dry-run)
set_tests_properties(DelaunayImageToMeshMutationCheck.EveryMutationApplies PROPERTIES TIMEOUT 120 LABELS reliability)
