#include "core/image_renderer.h"

#include <algorithm>
#include <atomic>
#include <mutex>

#include "core/error.h"
#include "core/plugin_loader.h"

namespace colony {
namespace {

// The backend's plugin (render/osmesa), loaded the first time something asks
// for an image renderer, so a run that draws nothing never loads OSMesa.
constexpr const char* kBackendPlugin = "colony_osmesa";

// Function-local statics: backends install themselves during static
// initialisation (of libcolony or of the plugin), in whatever order.
ImageRendererFactory& Factory() {
  static ImageRendererFactory factory = nullptr;
  return factory;
}
// Set while the backend's plugin is being loaded: its registrar's call to
// SetImageRendererFactory is then the load's result, not a choice.
std::atomic<bool> loading{false};
// A factory (or none) set by a caller: the plugin is then not loaded.
std::atomic<bool> chosen{false};
// Why the plugin could not be loaded, when it was there but failed.
std::string& LoadFailure() {
  static std::string failure;
  return failure;
}

void LoadBackendOnce() {
  static std::once_flag once;
  std::call_once(once, [] {
    if (chosen || Factory() != nullptr) return;
    loading = true;
    const std::string error = LoadPluginLibrary(kBackendPlugin, "");
    loading = false;
    // Only "no such file" for every candidate: a build without the renderer.
    // Otherwise the plugin is there and the loader says why it failed.
    if (!error.empty()) {
      for (size_t at = error.find("\n    "); at != std::string::npos;
           at = error.find("\n    ", at + 1)) {
        const size_t end = std::min(error.find('\n', at + 1), error.size());
        const std::string line = error.substr(at + 5, end - at - 5);
        if (line.find(" (") != std::string::npos &&
            line.find("(no such file)") == std::string::npos &&
            line.find("COLONY_PLUGIN_PATH") == std::string::npos)
          LoadFailure() += "\n    " + line;
      }
    }
  });
}

}  // namespace

ImageRendererFactory SetImageRendererFactory(ImageRendererFactory factory) {
  if (!loading) chosen = true;
  const ImageRendererFactory previous = Factory();
  Factory() = factory;
  return previous;
}

bool HaveImageRenderer() {
  LoadBackendOnce();
  return Factory() != nullptr;
}

std::unique_ptr<ImageRenderer> MakeImageRenderer(const Simulation& sim) {
  if (!HaveImageRenderer()) throw RuntimeFailure(NoImageRendererMessage("drawing an image"));
  return Factory()(sim);
}

std::string NoImageRendererMessage(const std::string& who) {
  if (!LoadFailure().empty()) {
    return who + " needs an image renderer, and its plugin could not be loaded:" + LoadFailure();
  }
  // The only backend is render/osmesa; its CMake option and packages.
  return who +
         " needs an image renderer, and this build has none: configure with "
         "-DCOLONY_WITH_OSMESA=ON (needs libosmesa6-dev and libassimp-dev)";
}

}  // namespace colony
