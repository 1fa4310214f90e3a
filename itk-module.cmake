# A short description: the README holds semicolons, which CMake would split into stray itk_module arguments.
set(DOCUMENTATION "Delaunay refinement meshing of segmented 3-D images into labelled tetrahedral meshes \
with guarantees: radius-edge ratio below 2, boundary triangle angles above 30 degrees, and a manifold \
boundary within a chosen distance of the object's surface, on CGAL's 3-D Delaunay triangulation.")

itk_module(DelaunayImageToMesh
  DEPENDS
    ITKCommon
    ITKMesh
    ITKImageFunction
  # Not linked by the library: the command-line program (examples/) reads images through them, and inside an ITK
  # tree they must be configured before this module for its find_package(ITK COMPONENTS ...) to see them.
  COMPILE_DEPENDS
    ITKIOImageBase
    ITKIONIFTI
    ITKIONRRD
    ITKIOMeta
  TEST_DEPENDS
    ITKTestKernel
    ITKIOImageBase
    ITKIONIFTI
    ITKIONRRD
    ITKIOMeta
    ITKImageGrid
    ITKThresholding
  DESCRIPTION
    "${DOCUMENTATION}"
  EXCLUDE_FROM_DEFAULT
  ENABLE_SHARED
)
