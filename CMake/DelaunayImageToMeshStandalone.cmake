# Plain-CMake build of the module against an installed ITK that lacks the remote-module CMake files
# (Debian's ITK 5.2.1). It builds the same library, tests and programs as the module path, with ordinary
# targets, CTest and GoogleTest.

if(NOT CMAKE_BUILD_TYPE AND NOT CMAKE_CONFIGURATION_TYPES)
  # Meshing is numeric work: an unoptimised build would make the tests and the program crawl.
  set(CMAKE_BUILD_TYPE Release CACHE STRING "Build type" FORCE)
endif()

set(DelaunayImageToMesh_ITK_COMPONENTS
  ITKCommon
  ITKMesh
  ITKImageFunction
  ITKIOImageBase
  ITKIONIFTI
  ITKIONRRD
  ITKIOMeta
  ITKIOGDCM
  ITKImageGrid
  ITKThresholding
  ITKTestKernel
)
find_package(ITK 5.2 REQUIRED COMPONENTS ${DelaunayImageToMesh_ITK_COMPONENTS})
include(${ITK_USE_FILE})

include(GNUInstallDirs)
set(CMAKE_RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/bin)
set(CMAKE_LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/lib)
set(CMAKE_ARCHIVE_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/lib)

# Before src/: CGAL's config declares its own BUILD_TESTING option (default OFF), which would win otherwise.
include(CTest)

add_subdirectory(src)

# The benchmark against CGAL Mesh_3 (bench/README.md); the sanitizer build leaves it out. Declared before test/,
# whose downstream FEM test also meshes with CGAL through bench/'s delaunay-bench-cgal-mesh.
option(DelaunayImageToMesh_BUILD_BENCHMARK "Build delaunay-bench" ON)

if(BUILD_TESTING)
  add_subdirectory(test)
endif()
add_subdirectory(examples)
if(DelaunayImageToMesh_BUILD_BENCHMARK AND EXISTS ${CMAKE_CURRENT_SOURCE_DIR}/bench/CMakeLists.txt)
  add_subdirectory(bench)
endif()

install(DIRECTORY include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/DelaunayImageToMesh)
install(FILES ${CMAKE_BINARY_DIR}/src/DelaunayImageToMeshExport.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/DelaunayImageToMesh)
