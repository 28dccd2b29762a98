// The CPU emulation's self-checks (cuda/emulation/self_check.cpp): each scene
// shows one thing the emulated runtime keeps of a GPU, by numbers whose
// answer is known. A build with a CUDA toolkit, or none, says it has no
// emulation.
#pragma once
#include <map>
#include <string>

namespace engine {

std::map<std::string, double> cuda_emulation_check(const std::string& scene);

}  // namespace engine
