#include "core/image_renderer.h"

#include "core/error.h"

namespace colony {
namespace {

// A function-local static: backends install themselves during static
// initialisation, in whatever order the objects' initialisers run.
ImageRendererFactory& Factory() {
  static ImageRendererFactory factory = nullptr;
  return factory;
}

}  // namespace

ImageRendererFactory SetImageRendererFactory(ImageRendererFactory factory) {
  const ImageRendererFactory previous = Factory();
  Factory() = factory;
  return previous;
}

bool HaveImageRenderer() { return Factory() != nullptr; }

std::unique_ptr<ImageRenderer> MakeImageRenderer(const Simulation& sim) {
  if (!HaveImageRenderer()) throw RuntimeFailure(NoImageRendererMessage("drawing an image"));
  return Factory()(sim);
}

std::string NoImageRendererMessage(const std::string& who) {
  // The only backend is render/osmesa; its CMake option and packages.
  return who +
         " needs an image renderer, and this build has none: configure with "
         "-DCOLONY_WITH_OSMESA=ON (needs libosmesa6-dev and libassimp-dev)";
}

}  // namespace colony
