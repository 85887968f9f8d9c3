// compare/ — comparing images: reading them whatever wrote them (OpenEXR, PFM, Radiance HDR, PNG, JPEG),
// their errors against a reference (metrics.h: MSE, relMSE, bias; compare.h: the whole comparison of
// `symphong compare`, region by region), the perceptual error FLIP (flip.h), and false-colour pictures of
// errors with their colour bars (error_map.h). Knows nothing of scenes or renders: the study and the
// command line hand it images.
//
// image_file.h — an image file read into linear RGB, with what kind of image it was.
#pragma once

#include "io/image.h"

#include <string>

namespace symphong {

struct ImageFile {
    Image image;                    ///< linear RGB (8- and 16-bit files through the sRGB curve)
    bool lowDynamicRange = false;   ///< PNG/JPEG/BMP/TGA: display values in [0,1] (LDR-FLIP applies)
    std::string format;             ///< "exr", "pfm", "hdr", "png", ...
};

/// Reads .exr, .pfm, .hdr, .png, .jpg/.jpeg, .bmp, .tga by extension (case-insensitive); a grey image
/// becomes (g, g, g). Throws MissingFileError when the file does not exist, InputError (naming the
/// file) for an unknown extension, a damaged file or values that are not finite.
ImageFile readImageFile(const std::string& path);

/// A Portable Float Map ("PF" colour or "Pf" grey, either byte order; rows stored bottom to top).
Image readPfm(const std::string& path);

}  // namespace symphong
