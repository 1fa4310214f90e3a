# The meshes downstream (issue #19): delaunay-image-to-mesh's output in a linear-elastic finite-element solve with
# DOLFINx (Debian python3-dolfinx, installed by scripts/setup.sh). Each test exits with 77 and says so when DOLFINx
# is missing; CTest reports it as skipped.
if(NOT TARGET DelaunayImageToMeshIO OR COMMAND itk_module_add_library)
  return()
endif()

set(downstream_output ${CMAKE_CURRENT_BINARY_DIR}/DownstreamOutput)

# The example an FEM user starts from still runs and carries the labels to the materials.
add_test(NAME DelaunayImageToMeshDownstream.ElasticityExample
  COMMAND ${DelaunayImageToMesh_TEST_PYTHON}
    ${CMAKE_CURRENT_SOURCE_DIR}/DelaunayImageToMeshDownstreamElasticityExample.py
    $<TARGET_FILE:delaunay-image-to-mesh> ${PROJECT_SOURCE_DIR}/examples ${downstream_output}/elasticity-example)

# Lame's thick shell under internal pressure: the displacement error falls at P1's rate, and is no worse than on CGAL
# Mesh_3's mesh of the same image (bench/'s delaunay-bench-cgal-mesh, when the benchmark is built).
if(DelaunayImageToMesh_BUILD_BENCHMARK AND EXISTS ${PROJECT_SOURCE_DIR}/bench/CMakeLists.txt)
  set(downstream_cgal_program $<TARGET_FILE:delaunay-bench-cgal-mesh>)
else()
  set(downstream_cgal_program -)
endif()
add_test(NAME DelaunayImageToMeshDownstream.LameShell
  COMMAND ${DelaunayImageToMesh_TEST_PYTHON} ${CMAKE_CURRENT_SOURCE_DIR}/DelaunayImageToMeshDownstreamLameShell.py
    $<TARGET_FILE:delaunay-image-to-mesh> ${downstream_cgal_program} ${PROJECT_SOURCE_DIR}/examples
    ${downstream_output}/lame-shell)

# PETSc and the BLAS underneath stay on one thread: ctest runs tests side by side on this project's 2 cores.
set_tests_properties(DelaunayImageToMeshDownstream.ElasticityExample DelaunayImageToMeshDownstream.LameShell
  PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 900
    ENVIRONMENT "PYTHONDONTWRITEBYTECODE=1;OMP_NUM_THREADS=1;OPENBLAS_NUM_THREADS=1")
