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

// Debian's ITK 5.2.1 was configured with GCC, and the itk_compiler_detection.h it installs knows GCC only: under
// clang it stops with "#error Unsupported compiler". Clang is GCC-compatible for all that ITK's headers ask of
// it (static_assert, alignment and deprecation attributes), so the fuzzer, which needs clang for libFuzzer, lets
// clang pass as the GCC 12 that built ITK while ITK's file is read, and only then (clang calls itself GCC 4.2,
// which ITK also refuses). This header is force-included first (-include),
// so that ITK's own later #include of the file finds its include guard set.
#pragma push_macro("__clang__")
#pragma push_macro("__GNUC__")
#pragma push_macro("__GNUC_MINOR__")
#undef __clang__
#undef __GNUC__
#undef __GNUC_MINOR__
#define __GNUC__ 12
#define __GNUC_MINOR__ 2
#include <itk_compiler_detection.h>
#pragma pop_macro("__GNUC_MINOR__")
#pragma pop_macro("__GNUC__")
#pragma pop_macro("__clang__")
