# Tests of the command-line program delaunay-image-to-mesh and of the quality report it prints. The program is
# built in examples/ (after this file is read, hence the generator expressions) whenever DelaunayImageToMeshIO is.
if(NOT TARGET DelaunayImageToMeshIO)
  return()
endif()

# The quality report on hand-made meshes whose answers are known.
add_executable(DelaunayImageToMeshCommandLineReportGTests DelaunayImageToMeshCommandLineQualityReportGTest.cxx)
# They read the JSON report back with nlohmann-json, the library that writes it.
find_package(nlohmann_json 3.10 REQUIRED)
target_link_libraries(DelaunayImageToMeshCommandLineReportGTests
  PRIVATE DelaunayImageToMeshIO GTest::gtest GTest::gtest_main nlohmann_json::nlohmann_json)
gtest_discover_tests(DelaunayImageToMeshCommandLineReportGTests DISCOVERY_TIMEOUT 120 PROPERTIES TIMEOUT 600)

# The report's count of a lost tissue's pieces against VTK's image connectivity filter, an independent reference.
find_package(VTK 9.1 COMPONENTS CommonCore CommonDataModel ImagingMorphological REQUIRED)
add_executable(DelaunayImageToMeshVoxelComponentsGTests DelaunayImageToMeshVoxelComponentsGTest.cxx)
target_include_directories(DelaunayImageToMeshVoxelComponentsGTests PRIVATE ${PROJECT_SOURCE_DIR}/src)
target_link_libraries(DelaunayImageToMeshVoxelComponentsGTests
  PRIVATE DelaunayImageToMeshIO ${VTK_LIBRARIES} GTest::gtest GTest::gtest_main)
vtk_module_autoinit(TARGETS DelaunayImageToMeshVoxelComponentsGTests MODULES ${VTK_LIBRARIES})
gtest_discover_tests(DelaunayImageToMeshVoxelComponentsGTests DISCOVERY_TIMEOUT 120 PROPERTIES TIMEOUT 600)

# The program is built by examples/, which only the plain-CMake build adds (the remote-module path does not).
if(COMMAND itk_module_add_library)
  return()
endif()

# Debian's python3 with python3-vtk9, python3-meshio and python3-numpy re-reads the meshes the program writes.
# (A python3 earlier on PATH, such as a pyenv one, usually lacks Debian's packages.) The test scripts import
# their shared module from the source tree, which must not collect __pycache__ directories.
set(DelaunayImageToMesh_TEST_PYTHON /usr/bin/python3 CACHE FILEPATH
  "Python interpreter with the vtk, meshio and numpy modules, for the command-line tests")

set(command_line_images ${CMAKE_CURRENT_BINARY_DIR}/CommandLineImages)
set(command_line_output ${CMAKE_CURRENT_BINARY_DIR}/CommandLineOutput)
set(command_line_program $<TARGET_FILE:delaunay-image-to-mesh>)

add_executable(DelaunayImageToMeshCommandLineGenerateImages DelaunayImageToMeshCommandLineGenerateImages.cxx)
target_link_libraries(DelaunayImageToMeshCommandLineGenerateImages PRIVATE ${ITK_LIBRARIES})
add_test(NAME DelaunayImageToMeshCommandLine.GenerateImages
  COMMAND DelaunayImageToMeshCommandLineGenerateImages ${command_line_images})
set_tests_properties(DelaunayImageToMeshCommandLine.GenerateImages PROPERTIES FIXTURES_SETUP CommandLineImages)

# Every output format, re-read with meshio (and VTK for .vtu/.vtk) and checked against the --report JSON.
foreach(extension vtu vtk msh mesh)
  add_test(NAME DelaunayImageToMeshCommandLine.OutputFormat.${extension}
    COMMAND ${DelaunayImageToMesh_TEST_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/DelaunayImageToMeshCommandLineOutputFormat.py
      ${command_line_program} ${command_line_images}/labels.nii.gz ${command_line_output}/format-${extension} ${extension})
endforeach()

# Every input format gives the same mesh; DICOM series and --iso work; progress and --quiet behave.
add_test(NAME DelaunayImageToMeshCommandLine.Inputs
  COMMAND ${DelaunayImageToMesh_TEST_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/DelaunayImageToMeshCommandLineInputs.py
    ${command_line_program} ${command_line_images} ${command_line_output}/inputs)

# Bad arguments (also in --config files), unreadable files and meshing failures: exit code 2 and a one-line message;
# --help, -h, --version, -V.
add_test(NAME DelaunayImageToMeshCommandLine.Errors
  COMMAND ${DelaunayImageToMesh_TEST_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/DelaunayImageToMeshCommandLineErrors.py
    ${command_line_program} ${command_line_images} ${command_line_output}/errors)

# The short options and --config files (TOML, INI) give the meshes of the long options.
add_test(NAME DelaunayImageToMeshCommandLine.Config
  COMMAND ${DelaunayImageToMesh_TEST_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/DelaunayImageToMeshCommandLineConfig.py
    ${command_line_program} ${command_line_images} ${command_line_output}/config)

# A tissue the mesh loses (two voxels at the default delta) reads as lost in the table and the JSON report.
add_test(NAME DelaunayImageToMeshCommandLine.LostTissue
  COMMAND ${DelaunayImageToMesh_TEST_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/DelaunayImageToMeshCommandLineLostTissue.py
    ${command_line_program} ${command_line_images} ${command_line_output}/lost-tissue)

# Radius-edge ratios, dihedral angles and boundary planar angles recomputed with NumPy from the written .vtu files,
# independently of the library's metric code.
add_test(NAME DelaunayImageToMeshCommandLine.IndependentQuality
  COMMAND ${DelaunayImageToMesh_TEST_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/DelaunayImageToMeshCommandLineIndependentQuality.py
    ${command_line_program} ${command_line_images} ${command_line_output}/independent-quality)
# The same on ITK's real segmentations (the brain mask and the k-means tissues) over δ, σ and ρ.
add_test(NAME DelaunayImageToMeshCommandLine.IndependentQualityOnRealImages
  COMMAND ${DelaunayImageToMesh_TEST_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/DelaunayImageToMeshCommandLineIndependentQuality.py
    ${command_line_program} ${command_line_images} ${command_line_output}/independent-quality-real
    ${DelaunayImageToMesh_EXAMPLES_DATA})
# Every topology option reaches the filter and turns its step off, on ITK's k-means tissues; the report records it.
add_test(NAME DelaunayImageToMeshCommandLine.TopologyOptions
  COMMAND ${DelaunayImageToMesh_TEST_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/DelaunayImageToMeshCommandLineTopologyOptions.py
    ${command_line_program} ${command_line_output}/topology-options ${DelaunayImageToMesh_EXAMPLES_DATA})
set_tests_properties(DelaunayImageToMeshCommandLine.TopologyOptions
  PROPERTIES TIMEOUT 600 ENVIRONMENT PYTHONDONTWRITEBYTECODE=1)

set_tests_properties(
  DelaunayImageToMeshCommandLine.IndependentQuality
  DelaunayImageToMeshCommandLine.IndependentQualityOnRealImages
  DelaunayImageToMeshCommandLine.OutputFormat.vtu
  DelaunayImageToMeshCommandLine.OutputFormat.vtk
  DelaunayImageToMeshCommandLine.OutputFormat.msh
  DelaunayImageToMeshCommandLine.OutputFormat.mesh
  DelaunayImageToMeshCommandLine.Inputs
  DelaunayImageToMeshCommandLine.Errors
  DelaunayImageToMeshCommandLine.Config
  DelaunayImageToMeshCommandLine.LostTissue
  PROPERTIES FIXTURES_REQUIRED CommandLineImages TIMEOUT 600 ENVIRONMENT PYTHONDONTWRITEBYTECODE=1)

# The picture scripts of examples/ still draw what they claim.
add_test(NAME DelaunayImageToMeshCommandLine.Pictures
  COMMAND ${DelaunayImageToMesh_TEST_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/DelaunayImageToMeshCommandLinePictures.py
    ${command_line_program} ${command_line_images}/labels.nii.gz ${PROJECT_SOURCE_DIR}/examples
    ${command_line_output}/pictures)
set_tests_properties(DelaunayImageToMeshCommandLine.Pictures
  PROPERTIES FIXTURES_REQUIRED CommandLineImages TIMEOUT 600 ENVIRONMENT PYTHONDONTWRITEBYTECODE=1)

# `cmake --install` installs the program, which then runs.
add_test(NAME DelaunayImageToMeshCommandLine.Install
  COMMAND sh ${CMAKE_CURRENT_SOURCE_DIR}/DelaunayImageToMeshCommandLineInstall.sh ${CMAKE_BINARY_DIR}
    ${CMAKE_CURRENT_BINARY_DIR}/CommandLineInstall)
set_tests_properties(DelaunayImageToMeshCommandLine.Install PROPERTIES TIMEOUT 600)
