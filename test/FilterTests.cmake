# Tests of itk::DelaunayImageToMeshFilter: ITK driver tests with --compare baselines, GoogleTest unit tests, and
# a compile-failure test for the 3-D-only static_assert. The real images come from the Debian package
# insighttoolkit5-examples.

set(DelaunayImageToMesh_EXAMPLES_DATA /usr/share/doc/insighttoolkit5-examples/examples/Data)
set(DelaunayImageToMesh_BASELINE ${CMAKE_CURRENT_SOURCE_DIR}/Baseline)
set(DelaunayImageToMesh_TEST_OUTPUT ${CMAKE_CURRENT_BINARY_DIR}/Output)
file(MAKE_DIRECTORY ${DelaunayImageToMesh_TEST_OUTPUT})

# ---- Driver tests ----------------------------------------------------------------------------------------
# Debian's ITK has no CreateTestDriver: the same driver is made with create_test_sourcelist and ITK's installed
# driver fragments, which give the usual --compare, --compareIntensityTolerance and
# --compareNumberOfPixelsTolerance arguments. Test files are listed without a directory prefix, or the
# generated function names break.
set(DelaunayImageToMeshFilterDriverTests
  itkDelaunayImageToMeshFilterTest.cxx
  itkDelaunayImageToMeshFilterRealImageTest.cxx
)
set(CMAKE_TESTDRIVER_BEFORE_TESTMAIN "#include \"itkTestDriverBeforeTest.inc\"")
set(CMAKE_TESTDRIVER_AFTER_TESTMAIN "#include \"itkTestDriverAfterTest.inc\"")
create_test_sourcelist(DelaunayImageToMeshFilterDriverSources
  DelaunayImageToMeshFilterTestDriver.cxx
  ${DelaunayImageToMeshFilterDriverTests}
  EXTRA_INCLUDE itkTestDriverIncludeRequiredIOFactories.h
  FUNCTION ProcessArgumentsAndRegisterRequiredFactories
)
unset(CMAKE_TESTDRIVER_BEFORE_TESTMAIN)
unset(CMAKE_TESTDRIVER_AFTER_TESTMAIN)
add_executable(DelaunayImageToMeshFilterTestDriver ${DelaunayImageToMeshFilterDriverSources})
target_link_libraries(DelaunayImageToMeshFilterTestDriver PRIVATE DelaunayImageToMesh ${ITK_LIBRARIES})

add_test(NAME itkDelaunayImageToMeshFilterTest
  COMMAND DelaunayImageToMeshFilterTestDriver itkDelaunayImageToMeshFilterTest)

# Regression on the real images at δ = 4 mm: the mesh voxelised onto the input grid against a stored label
# image (driver --compare), and the mesh invariants against a stored text file (tetrahedra and boundary
# triangles within ± 3 %, per-tissue tetrahedra within ± 3 %, topology exactly unless countsOnly).
# --compareIntensityTolerance 0: the driver's default (2) would hide every label change of 1 or 2.
# --compareNumberOfPixelsTolerance: 2 % of the object voxels. Measured on this machine (test/Baseline/README.md),
# any perturbation of the refinement's cascade, even δ + 1 % (a stand-in for another platform's rounding),
# re-labels a band of voxels along the boundary: 1.4 % of the brain mask's voxels (1.3-1.6 % for δ ± 10 %);
# a one-voxel shift re-labels 4.9-6.2 %, δ = 6 mm 2.1 %. The counts catch the smaller material changes
# (δ ± 10 % moves them by 19-30 %, δ + 5 % by more than the 3 % allowed).
function(delaunay_add_real_image_test name image delta labels pixel_tolerance radius_tolerance)
  add_test(NAME ${name}
    COMMAND DelaunayImageToMeshFilterTestDriver
      --compare ${DelaunayImageToMesh_BASELINE}/${name}.nrrd ${DelaunayImageToMesh_TEST_OUTPUT}/${name}.nrrd
      --compareIntensityTolerance 0
      --compareRadiusTolerance ${radius_tolerance}
      --compareNumberOfPixelsTolerance ${pixel_tolerance}
      itkDelaunayImageToMeshFilterRealImageTest
        ${DelaunayImageToMesh_EXAMPLES_DATA}/${image} ${delta} ${labels}
        ${DelaunayImageToMesh_TEST_OUTPUT}/${name}.nrrd
        ${DelaunayImageToMesh_BASELINE}/${name}.txt
        ${DelaunayImageToMesh_TEST_OUTPUT}/${name}.txt
        ${ARGN})
  math(EXPR timeout "300 * ${DelaunayImageToMesh_TEST_TIMEOUT_FACTOR}")
  set_tests_properties(${name} PROPERTIES TIMEOUT ${timeout})
endfunction()

# The brain mask (every non-zero voxel, one object) has 128,472 voxels: 2 % is 2,569.
delaunay_add_real_image_test(itkDelaunayImageToMeshFilterBrainMaskTest
  KmeansTest_T1RawSkullStrip.nii.gz 4 nonzero 2569 0)
# The k-means tissues: label 1 is the background class (729,202 voxels, 92 % of the border voxels), labels 2..6
# the tissues, 286,480 voxels: 2 % is 5,729. The segmentation is speckle at the voxel scale (22,763 voxel edges
# where tissue 2 touches itself only diagonally), far below δ, so which speckle a tetrahedron captures is
# chaotic: δ ± 1 % re-labels 27 % of the voxels and changes tissue 5's boundary components from 83 to 97 and
# tissue 2's genus from 193 to 135. Hence a one-voxel search radius (which brings δ ± 1 % down to 0.7 %; δ = 6 mm
# gives 2.1 %; the brain-mask test, with radius 0, is the one that sees one-voxel shifts) and counts only.
delaunay_add_real_image_test(itkDelaunayImageToMeshFilterKmeansTissuesTest
  KmeansTest_T1KmeansPrelimSegmentation.nii.gz 4 2,3,4,5,6 5729 1 countsOnly)

# ---- GoogleTest ------------------------------------------------------------------------------------------
if(TARGET DelaunayImageToMeshIO)
  add_executable(itkDelaunayImageToMeshFilterGTests itkDelaunayImageToMeshFilterGTest.cxx itkImageLabelSelectionGTest.cxx)
  target_link_libraries(itkDelaunayImageToMeshFilterGTests PRIVATE
    DelaunayImageToMesh DelaunayImageToMeshIO ${ITK_LIBRARIES} GTest::gtest_main)
  # The last resort for flat tetrahedra is reached through a hook only tests use (src/DelaunayRefinementTestHooks.h).
  target_include_directories(itkDelaunayImageToMeshFilterGTests PRIVATE ${PROJECT_SOURCE_DIR}/src)
  target_compile_definitions(itkDelaunayImageToMeshFilterGTests PRIVATE
    DelaunayImageToMesh_EXAMPLES_DATA="${DelaunayImageToMesh_EXAMPLES_DATA}"
    DelaunayImageToMesh_TEST_INPUT="${CMAKE_CURRENT_SOURCE_DIR}/Input")
  # The prefix keeps the test names apart from other GoogleTest executables' (and selects them all: -R itkDelaunay).
  math(EXPR filter_gtest_timeout "300 * ${DelaunayImageToMesh_TEST_TIMEOUT_FACTOR}")
  gtest_discover_tests(itkDelaunayImageToMeshFilterGTests
    TEST_PREFIX "itkDelaunayImageToMeshFilterGTest."
    DISCOVERY_TIMEOUT 120
    PROPERTIES TIMEOUT ${filter_gtest_timeout})
endif()

# ---- Bit-exact mesh fingerprints ---------------------------------------------------------------------------
# Proves that a change meant to move code changed no mesh (test/Baseline/MeshFingerprints.txt says how a change
# meant to alter meshes updates it).
add_executable(DelaunayImageToMeshFingerprintGTests DelaunayImageToMeshFingerprintGTest.cxx)
target_link_libraries(DelaunayImageToMeshFingerprintGTests PRIVATE
  DelaunayImageToMesh ${ITK_LIBRARIES} GTest::gtest_main)
target_compile_definitions(DelaunayImageToMeshFingerprintGTests PRIVATE
  DelaunayImageToMesh_EXAMPLES_DATA="${DelaunayImageToMesh_EXAMPLES_DATA}"
  DelaunayImageToMesh_FINGERPRINT_BASELINE="${DelaunayImageToMesh_BASELINE}/MeshFingerprints.txt")
math(EXPR fingerprint_timeout "600 * ${DelaunayImageToMesh_TEST_TIMEOUT_FACTOR}")
gtest_discover_tests(DelaunayImageToMeshFingerprintGTests DISCOVERY_TIMEOUT 120 PROPERTIES TIMEOUT ${fingerprint_timeout})

# ---- Topology at the scale of delta, on generated hostile shapes (issue #14) ---------------------------------
add_executable(itkDelaunayImageToMeshFilterTopologyGTests itkDelaunayImageToMeshFilterTopologyGTest.cxx)
target_link_libraries(itkDelaunayImageToMeshFilterTopologyGTests PRIVATE
  DelaunayImageToMesh ${ITK_LIBRARIES} GTest::gtest_main)
gtest_discover_tests(itkDelaunayImageToMeshFilterTopologyGTests DISCOVERY_TIMEOUT 120 PROPERTIES TIMEOUT 600)

# ---- Compile-time rejection of 2-D images ------------------------------------------------------------------
# Passes when compiling a 2-D instantiation fails with the filter's static_assert message. The include
# directories are the library's (the module's include/ and the generated export header) and ITK's.
set(DelaunayImageToMesh_ITK_INCLUDE_FLAGS ${ITK_INCLUDE_DIRS})
list(TRANSFORM DelaunayImageToMesh_ITK_INCLUDE_FLAGS PREPEND "-I")
add_test(NAME itkDelaunayImageToMeshFilter2DCompileFailTest
  COMMAND ${CMAKE_CXX_COMPILER} -std=c++17 -fsyntax-only
    "-I$<JOIN:$<TARGET_PROPERTY:DelaunayImageToMesh,INCLUDE_DIRECTORIES>,;-I>"
    ${DelaunayImageToMesh_ITK_INCLUDE_FLAGS}
    ${CMAKE_CURRENT_SOURCE_DIR}/itkDelaunayImageToMeshFilter2DCompileFail.cxx
  COMMAND_EXPAND_LISTS)
set_tests_properties(itkDelaunayImageToMeshFilter2DCompileFailTest PROPERTIES
  PASS_REGULAR_EXPRESSION "meshes 3-D images only"
  TIMEOUT 120)
