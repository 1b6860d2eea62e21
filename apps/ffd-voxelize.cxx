/*=========================================================================
 *
 *  Copyright NumFOCUS
 *
 *  Licensed under the Apache License, Version 2.0 (the "License");
 *  you may not use this file except in compliance with the License.
 *  You may obtain a copy of the License at
 *
 *         http://www.apache.org/licenses/LICENSE-2.0.txt
 *
 *  Unless required by applicable law or agreed to in writing, software
 *  distributed under the License is distributed on an "AS IS" BASIS,
 *  WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
 *  See the License for the specific language governing permissions and
 *  limitations under the License.
 *
 *=========================================================================*/
// ffd-voxelize: turns a triangle mesh into a voxel image (occupancy, solid, signed distance, band
// mask or winding number) with TriangleMeshToVoxelImageFilter.
//
//   ffd-voxelize MESH OUTPUT_IMAGE --mode occupancy|solid|sdf|band|winding --voxel-size S
//                [--margin M] [--reference IMAGE] [--band-width B] [--exact] [--unsigned]
//                [--beta BETA] [--threads N] [--report FILE.json]
//
// The outputs are checked before any work, written to temporary files next to them, read back and renamed into
// place together (ffd::OutputFiles), so a failed run changes no file. Errors are one line on stderr and a non-zero
// exit code.

#include "FFDAllocatorSettings.h"
#include "FFDInputFiles.h"
#include "FFDProgramMeshIO.h"
#include "FFDOutputFiles.h"
#include "FFDProgramMessages.h"
#include "FFDProgramSupport.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "itkImageIOFactory.h"
#include "itkImageRegionConstIterator.h"
#include "itkMesh.h"
#include "itkMeshFileReader.h"
#include "itkMultiThreaderBase.h"
#include "itkRegisterFFDShapeMatchingMeshIOFactories.h"
#include "itkTriangleMeshToVoxelImageFilter.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <vector>

namespace
{
// Double coordinates (itk::Mesh<double, 3> stores float coordinates).
using MeshType = itk::Mesh<double, 3, itk::DefaultStaticMeshTraits<double, 3, 3, double, double, double>>;
using MaskImageType = itk::Image<unsigned char, 3>;
using RealImageType = itk::Image<float, 3>;
using ModeEnum = itk::TriangleMeshToVoxelImageFilterEnums::Mode;
using ffd::ClockType;
using ffd::JsonString;
using ffd::OneLine;
using ffd::SecondsSince;

// What the run is doing, for the message when memory runs out ("not enough memory to ...").
std::string CurrentTask = "start";

const char * const Usage =
  "usage: ffd-voxelize MESH OUTPUT_IMAGE --mode occupancy|solid|sdf|band|winding --voxel-size S\n"
  "                    [--margin M] [--reference IMAGE] [--band-width B] [--exact] [--unsigned]\n"
  "                    [--beta BETA] [--threads N] [--report FILE.json]\n"
  "  MESH          OFF, OBJ, VTK, VTP, STL or PLY triangle mesh\n"
  "  OUTPUT_IMAGE  any single-file ITK image format (.mha, .nrrd, .nii, .nii.gz, ...)\n"
  "  --mode        occupancy: voxels the surface passes through; solid: inside (winding number);\n"
  "                sdf: signed distance (negative inside, float); band: voxels within the band;\n"
  "                winding: raw generalized winding number (float)\n"
  "  --voxel-size  voxel edge length S > 0 (grid from the mesh bounds; ignored with --reference)\n"
  "  --margin      space around the mesh bounds, default 3 voxels\n"
  "  --reference   copy the geometry of this image (only its header is read)\n"
  "  --band-width  band half width for sdf and band, default 3 voxels\n"
  "  --exact       sdf: exact distance everywhere instead of clamped beyond the band\n"
  "  --unsigned    sdf: unsigned distance (open surfaces)\n"
  "  --beta        fast winding number accuracy, default 2 (0: exact)\n"
  "  --threads     number of threads, default all\n"
  "  --report      write a JSON report (geometry, counts, times)\n";

struct Options
{
  std::string meshFile;
  std::string outputFile;
  std::string mode;
  double      voxelSize{ 0.0 };
  double      margin{ -1.0 };
  std::string referenceFile;
  double      bandWidth{ -1.0 };
  bool        exact{ false };
  bool        unsignedDistance{ false };
  double      beta{ 2.0 };
  int         threads{ 0 };
  std::string reportFile;
};

// Errors of the command line (exit code 2) and of the run (exit code 1).
struct UsageError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

double
ParseNumber(const std::string & option, const std::string & text)
{
  return ffd::ParseNumber<UsageError>(option, text);
}

Options
ParseArguments(int argc, char * argv[])
{
  Options                  options;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i)
  {
    const std::string argument = argv[i];
    const auto        value = [&]() -> std::string {
      if (i + 1 >= argc)
      {
        throw UsageError(argument + " needs a value");
      }
      return argv[++i];
    };
    if (argument == "--help" || argument == "-h")
    {
      std::cout << Usage;
      std::exit(EXIT_SUCCESS);
    }
    else if (argument == "--mode")
    {
      options.mode = value();
    }
    else if (argument == "--voxel-size")
    {
      options.voxelSize = ParseNumber(argument, value());
    }
    else if (argument == "--margin")
    {
      options.margin = ParseNumber(argument, value());
    }
    else if (argument == "--reference")
    {
      options.referenceFile = value();
    }
    else if (argument == "--band-width")
    {
      options.bandWidth = ParseNumber(argument, value());
    }
    else if (argument == "--exact")
    {
      options.exact = true;
    }
    else if (argument == "--unsigned")
    {
      options.unsignedDistance = true;
    }
    else if (argument == "--beta")
    {
      options.beta = ParseNumber(argument, value());
    }
    else if (argument == "--threads")
    {
      const double threads = ParseNumber(argument, value());
      if (threads < 1 || threads != std::floor(threads) || threads > 4096)
      {
        throw UsageError("--threads needs a whole number >= 1");
      }
      options.threads = static_cast<int>(threads);
    }
    else if (argument == "--report")
    {
      options.reportFile = value();
    }
    else if (argument.size() > 1 && argument[0] == '-')
    {
      throw UsageError("unknown option " + argument);
    }
    else
    {
      positional.push_back(argument);
    }
  }
  if (positional.size() != 2)
  {
    throw UsageError("expected MESH and OUTPUT_IMAGE, got " + std::to_string(positional.size()) + " file names");
  }
  options.meshFile = positional[0];
  options.outputFile = positional[1];
  if (options.mode.empty())
  {
    throw UsageError("--mode is required");
  }
  if (options.mode != "occupancy" && options.mode != "solid" && options.mode != "sdf" && options.mode != "band" &&
      options.mode != "winding")
  {
    throw UsageError("--mode must be occupancy, solid, sdf, band or winding, not '" + options.mode + "'");
  }
  if (options.referenceFile.empty() && !(options.voxelSize > 0.0))
  {
    throw UsageError("--voxel-size must be given and > 0 (or use --reference)");
  }
  if (options.margin < 0.0)
  {
    options.margin = 3.0 * options.voxelSize;
  }
  if (options.bandWidth < 0.0 && options.voxelSize > 0.0)
  {
    options.bandWidth = 3.0 * options.voxelSize;
  }
  // Two-file formats cannot be renamed into place atomically.
  for (const char * extension : { ".mhd", ".hdr", ".nhdr" })
  {
    const std::string e = extension;
    if (options.outputFile.size() >= e.size() &&
        options.outputFile.compare(options.outputFile.size() - e.size(), e.size(), e) == 0)
    {
      throw UsageError("OUTPUT_IMAGE must be a single-file format (.mha, .nrrd, .nii, .nii.gz, ...), not " + e);
    }
  }
  return options;
}

template <typename TVector>
std::string
JsonArray(const TVector & values)
{
  std::ostringstream out;
  out.precision(17);
  out << '[';
  for (unsigned int i = 0; i < 3; ++i)
  {
    out << (i ? ", " : "") << values[i];
  }
  out << ']';
  return out.str();
}

// The temporary names of the outputs (image, report), declared, and so checked, before any work.
struct OutputNames
{
  std::string image;
  std::string report;
};

OutputNames
DeclareOutputs(const Options & options, ffd::OutputFiles & outputs)
{
  OutputNames names;
  outputs.AddInput(options.meshFile);
  if (!options.referenceFile.empty())
  {
    outputs.AddInput(options.referenceFile);
  }
  names.image = outputs.Add(options.outputFile, "OUTPUT_IMAGE", {}, false);
  if (itk::ImageIOFactory::CreateImageIO(names.image.c_str(), itk::IOFileModeEnum::WriteMode).IsNull())
  {
    throw std::runtime_error("OUTPUT_IMAGE must name an image format ITK can write (.mha, .nrrd, .nii, .nii.gz, "
                             "...), not '" +
                             options.outputFile + "'");
  }
  if (!options.reportFile.empty())
  {
    names.report = outputs.Add(options.reportFile, "--report", {}, true);
  }
  return names;
}

template <typename TImage>
int
Run(const Options &     options,
    ModeEnum            mode,
    const MeshType *    mesh,
    double              readSeconds,
    ffd::OutputFiles &  outputs,
    const OutputNames & names)
{
  using FilterType = itk::TriangleMeshToVoxelImageFilter<MeshType, TImage>;
  auto filter = FilterType::New();
  filter->SetInput(mesh);
  filter->SetMode(mode);
  filter->SetBeta(options.beta);
  filter->SetExactDistance(options.exact);
  filter->SetUnsignedDistance(options.unsignedDistance);
  if (options.bandWidth >= 0.0)
  {
    filter->SetBandWidth(options.bandWidth);
  }
  using ReferenceReaderType = itk::ImageFileReader<RealImageType>;
  typename ReferenceReaderType::Pointer referenceReader;
  if (!options.referenceFile.empty())
  {
    CurrentTask = "read the reference image";
    ffd::CheckInputFile<std::runtime_error>(options.referenceFile, "reference image", ffd::MaximumImageFileSize);
    referenceReader = ReferenceReaderType::New();
    referenceReader->SetFileName(options.referenceFile);
    try
    {
      // MetaIO and NIfTI print their complaints on stderr before ITK throws: kept off it.
      ffd::LibraryOutputCapture capture;
      referenceReader->UpdateOutputInformation();
    }
    catch (const itk::ExceptionObject & error)
    {
      throw std::runtime_error("cannot read reference image '" + options.referenceFile +
                               "': " + OneLine(error.GetDescription()));
    }
    filter->SetReferenceImage(referenceReader->GetOutput());
  }
  else
  {
    typename FilterType::SpacingType spacing;
    spacing.Fill(options.voxelSize);
    filter->SetGeometryFromMeshBounds(spacing, options.margin);
  }

  CurrentTask = "voxelize the mesh";
  const auto start = ClockType::now();
  filter->Update();
  const double   voxelizeSeconds = SecondsSince(start);
  const TImage * output = filter->GetOutput();

  double                                marked = 0.0;
  double                                minimum = std::numeric_limits<double>::infinity();
  double                                maximum = -minimum;
  itk::ImageRegionConstIterator<TImage> it(output, output->GetBufferedRegion());
  for (; !it.IsAtEnd(); ++it)
  {
    const double value = static_cast<double>(it.Get());
    marked += value == static_cast<double>(filter->GetInsideValue());
    minimum = std::min(minimum, value);
    maximum = std::max(maximum, value);
  }

  CurrentTask = "write the image";
  const auto writeStart = ClockType::now();
  try
  {
    auto writer = itk::ImageFileWriter<TImage>::New();
    writer->SetInput(output);
    writer->SetFileName(names.image);
    writer->UseCompressionOn();
    writer->Update();
    // Read back: a full disk or a file size limit can leave a cut file that a writer does not notice.
    auto reader = itk::ImageFileReader<TImage>::New();
    reader->SetFileName(names.image);
    reader->Update();
    if (reader->GetOutput()->GetLargestPossibleRegion() != output->GetLargestPossibleRegion())
    {
      throw std::runtime_error("the written file does not read back whole");
    }
  }
  catch (const itk::ExceptionObject & error)
  {
    throw std::runtime_error("cannot write '" + options.outputFile + "': " + OneLine(error.GetDescription()) +
                             " (is the disk full or a file size limit reached?)");
  }
  const double writeSeconds = SecondsSince(writeStart);

  const auto size = output->GetLargestPossibleRegion().GetSize();
  std::cerr << "ffd-voxelize: " << filter->GetNumberOfTriangles() << " triangles ("
            << filter->GetNumberOfDegenerateTriangles() << " degenerate skipped), " << size[0] << "x" << size[1] << "x"
            << size[2] << " voxels in " << voxelizeSeconds << " s -> " << options.outputFile << std::endl;

  if (!options.reportFile.empty())
  {
    std::ostringstream report;
    std::ostringstream sizeText;
    sizeText << '[' << size[0] << ", " << size[1] << ", " << size[2] << ']';
    report.precision(17);
    report << "{\n"
           << "  \"mesh\": " << JsonString(options.meshFile) << ",\n"
           << "  \"output\": " << JsonString(options.outputFile) << ",\n"
           << "  \"mode\": " << JsonString(options.mode) << ",\n"
           << "  \"reference\": "
           << (options.referenceFile.empty() ? std::string("null") : JsonString(options.referenceFile)) << ",\n"
           << "  \"voxel_size\": " << options.voxelSize << ",\n"
           << "  \"margin\": " << options.margin << ",\n"
           << "  \"band_width\": " << options.bandWidth << ",\n"
           << "  \"beta\": " << options.beta << ",\n"
           << "  \"exact_distance\": " << (options.exact ? "true" : "false") << ",\n"
           << "  \"unsigned_distance\": " << (options.unsignedDistance ? "true" : "false") << ",\n"
           << "  \"size\": " << sizeText.str() << ",\n"
           << "  \"spacing\": " << JsonArray(output->GetSpacing()) << ",\n"
           << "  \"origin\": " << JsonArray(output->GetOrigin()) << ",\n"
           << "  \"number_of_voxels\": " << output->GetLargestPossibleRegion().GetNumberOfPixels() << ",\n"
           << "  \"number_of_triangles\": " << filter->GetNumberOfTriangles() << ",\n"
           << "  \"number_of_degenerate_triangles\": " << filter->GetNumberOfDegenerateTriangles() << ",\n"
           << "  \"inside_value_voxels\": " << marked << ",\n"
           << "  \"minimum\": " << minimum << ",\n"
           << "  \"maximum\": " << maximum << ",\n"
           << "  \"threads\": " << itk::MultiThreaderBase::GetGlobalDefaultNumberOfThreads() << ",\n"
           << "  \"seconds\": { \"read\": " << readSeconds << ", \"voxelize\": " << voxelizeSeconds
           << ", \"write\": " << writeSeconds << " }\n"
           << "}\n";
    outputs.WriteText(options.reportFile, report.str());
  }
  outputs.Commit();
  return EXIT_SUCCESS;
}

} // namespace

int
main(int argc, char * argv[])
{
  ffd::KeepFreedMemoryForReuse();
  ffd::CollectLibraryMessages();
  Options options;
  try
  {
    options = ParseArguments(argc, argv);
  }
  catch (const UsageError & error)
  {
    std::cerr << "ffd-voxelize: error: " << error.what() << " (see --help)" << std::endl;
    return 2;
  }

  try
  {
    if (options.threads > 0)
    {
      itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(options.threads);
    }
    itk::RegisterFFDShapeMatchingMeshIOFactories();
    CurrentTask = "read the mesh";
    ffd::CheckInputFile<std::runtime_error>(options.meshFile, "mesh", ffd::MaximumMeshFileSize);
    ffd::OutputFiles  outputs("ffd-voxelize");
    const OutputNames names = DeclareOutputs(options, outputs);
    const auto        readStart = ClockType::now();
    auto              reader = itk::MeshFileReader<MeshType>::New();
    reader->SetFileName(options.meshFile);
    try
    {
      ffd::LibraryOutputCapture capture;
      reader->Update();
    }
    catch (const itk::ExceptionObject & error)
    {
      throw std::runtime_error("cannot read mesh '" + options.meshFile + "': " + OneLine(error.GetDescription()));
    }
    const double     readSeconds = SecondsSince(readStart);
    const MeshType * mesh = reader->GetOutput();

    if (options.mode == "occupancy")
    {
      return Run<MaskImageType>(options, ModeEnum::Occupancy, mesh, readSeconds, outputs, names);
    }
    if (options.mode == "solid")
    {
      return Run<MaskImageType>(options, ModeEnum::Solid, mesh, readSeconds, outputs, names);
    }
    if (options.mode == "band")
    {
      return Run<MaskImageType>(options, ModeEnum::BandMask, mesh, readSeconds, outputs, names);
    }
    if (options.mode == "winding")
    {
      return Run<RealImageType>(options, ModeEnum::WindingNumber, mesh, readSeconds, outputs, names);
    }
    return Run<RealImageType>(options, ModeEnum::SignedDistance, mesh, readSeconds, outputs, names);
  }
  catch (const itk::ExceptionObject & error)
  {
    std::cerr << "ffd-voxelize: error: " << OneLine(error.GetDescription()) << std::endl;
  }
  catch (const std::bad_alloc &)
  {
    std::cerr << "ffd-voxelize: error: not enough memory to " << CurrentTask << std::endl;
  }
  catch (const std::exception & error)
  {
    std::cerr << "ffd-voxelize: error: " << OneLine(error.what()) << std::endl;
  }
  return EXIT_FAILURE;
}
