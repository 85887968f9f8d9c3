// `symphong --version`: the program's version and the libraries it was built with (each layer reports
// its own: Embree from accel/, Assimp from scene/, OpenEXR and libpng from io/, oneTBB from render/,
// MPI from distrib/).
#include "accel/accel.h"
#include "cli/commands.h"
#include "distrib/mpi_job.h"
#include "io/image.h"
#include "render/renderer.h"
#include "scene/scene.h"

#include <fmt/format.h>

namespace symphong {

std::string versionText() {
    return fmt::format(
        "symphong {}\n"
        "built with: Embree {}, oneTBB {}, Assimp {}, OpenEXR {}, libpng {}, MPI: {}, fmt {}.{}.{}",
        SYMPHONG_VERSION, embreeVersion(), tbbVersion(), assimpVersion(), openexrVersion(), libpngVersion(), mpiVersion(),
        FMT_VERSION / 10000, FMT_VERSION / 100 % 100, FMT_VERSION % 100);
}

}  // namespace symphong
