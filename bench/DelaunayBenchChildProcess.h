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
#ifndef DelaunayBenchChildProcess_h
#define DelaunayBenchChildProcess_h

#include "DelaunayBenchMeshers.h"

#include <cstddef>
#include <functional>
#include <optional>
#include <string>

namespace delaunay_bench
{

/** The high-water mark of this process's resident memory (Linux VmHWM), bytes. */
std::size_t
PeakResidentBytes();

/** A mesher's output and the memory it added. */
struct MeasuredRun
{
  MesherOutput output;
  /** The mesher's MesherOutput::peakResidentBytes minus the child's resident memory when it started. */
  std::size_t meshingMemoryBytes{ 0 };
};

/** Runs `mesher` in a forked child and brings its output back through a pipe, so that each measurement of
 * peak memory sees one mesher alone. A forked child starts with the parent's resident pages and high-water
 * mark (which is why its ru_maxrss from wait4 would mostly measure the parent); it therefore returns free
 * heap to the system, resets its high-water mark (/proc/self/clear_refs) and counts from its resident size.
 * \throws std::runtime_error with the child's message when the mesher throws or the child dies. */
MeasuredRun
RunInChildProcess(const std::function<MesherOutput()> & mesher);

/** Limits on one run: CPU seconds (the meshers are sequential, so about the wall time) and address space. */
struct ResourceCap
{
  double      cpuSeconds{ 300.0 };
  std::size_t addressSpaceBytes{ std::size_t{ 8 } << 30 };
};

/** A run within `cap`, or nullopt with `overCap` saying which limit it reached: the child gets the limits as
 * setrlimit(RLIMIT_CPU) and setrlimit(RLIMIT_AS), so a run over the time cap is killed by SIGXCPU and one over the
 * memory cap fails to allocate. Any other failure throws, as RunInChildProcess() does. */
std::optional<MeasuredRun>
RunInChildProcessWithin(const std::function<MesherOutput()> & mesher, const ResourceCap & cap, std::string & overCap);

} // namespace delaunay_bench

#endif
