// Matches a source mesh to a target mesh with the default method (go+cpd) and writes the deformed source:
//   MatchMeshes SOURCE TARGET OUTPUT [CONTROL_POINTS_PER_AXIS] [VOXEL_SIZE]
// The same as: ffd-match --source SOURCE --target TARGET --output OUTPUT --grid N --voxel-size S
#include "itkMeshFileReader.h"
#include "itkMeshFileWriter.h"
#include "itkMeshShapeMatchingFilter.h"
#include "itkRegisterFFDShapeMatchingMeshIOFactories.h"

#include <cstdlib>
#include <iostream>
#include <string>

int
main(int argc, char * argv[])
{
  if (argc < 4)
  {
    std::cerr << "usage: " << argv[0] << " SOURCE TARGET OUTPUT [CONTROL_POINTS_PER_AXIS] [VOXEL_SIZE]\n";
    return EXIT_FAILURE;
  }
  // Double-precision coordinates (itk::Mesh<double, 3> stores its points as float).
  using MeshType = itk::Mesh<double, 3, itk::DefaultStaticMeshTraits<double, 3, 3, double, double, double>>;
  itk::RegisterFFDShapeMatchingMeshIOFactories(); // STL, PLY, VTP and the strict OFF/OBJ/VTK readers
  try
  {
    auto source = itk::MeshFileReader<MeshType>::New();
    source->SetFileName(argv[1]);
    auto target = itk::MeshFileReader<MeshType>::New();
    target->SetFileName(argv[2]);

    auto matching = itk::MeshShapeMatchingFilter<MeshType>::New();
    matching->SetSourceMesh(source->GetOutput());
    matching->SetTargetMesh(target->GetOutput());
    matching->SetMethod(itk::FFDShapeMatchingEnums::Method::GOCPD); // the default; GO, MRF, Par... selectable
    matching->SetNumberOfControlPointsPerAxis(argc > 4 ? std::stoi(argv[4]) : 20);
    matching->SetVoxelSize(argc > 5 ? std::stod(argv[5]) : 1.0);

    auto writer = itk::MeshFileWriter<MeshType>::New();
    writer->SetInput(matching->GetOutput());
    writer->SetFileName(argv[3]);
    writer->Update();
  }
  catch (const itk::ExceptionObject & error)
  {
    std::cerr << error.GetDescription() << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
