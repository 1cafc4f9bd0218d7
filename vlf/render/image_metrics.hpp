// image_metrics.hpp — the error of a rendered view against a path-traced reference, as a
// viewer sees it (docs/rendering.md "Accuracy"). A lamp's pixels hold its exactly known
// emission (radiance 17 in the Cornell box against 0.1–1 elsewhere), so a whole-image
// relative RMSE is dominated by them and says little about the light the bake carries.
// The figures here are therefore also taken *away from emitters*: over the pixels whose
// 3x3 neighbourhood holds no pixel that sees an emitting face (Renderer::emitter_mask).
//
// Images are linear radiance (W m^-2 sr^-1); the functions throw Error when the sizes of
// the images (and mask) differ.
#pragma once

#include <cstddef>

#include "vlf/render/image_io.hpp"

namespace vlf {

// The pixels of `mask` whose (2r+1) x (2r+1) neighbourhood (clipped at the image border)
// holds no set pixel: with r = 1, the pixels "away from" the set ones.
PixelMask away_from(const PixelMask& mask, int radius = 1);

// sqrt(sum |a - ref|^2 / sum |ref|^2) over all pixels (RGB as a 3-vector); 0 when both
// sums are 0, infinity when only the reference's is.
double relative_rmse(const Image& a, const Image& ref);
// The same over the pixels set in `where`.
double relative_rmse(const Image& a, const Image& ref, const PixelMask& where);

// Per channel: sum of a / sum of ref over the pixels set in `where` (1 means the mean
// radiance is right). A channel whose sums are both 0 gives 1, whose reference sum alone
// is 0 gives infinity.
Rgb mean_ratio(const Image& a, const Image& ref, const PixelMask& where);

// Everything `walkthrough --reference` prints and the accuracy tests assert.
struct ImageError {
    double rmse = 0.0;       // relative RMSE, whole image
    double rmse_away = 0.0;  // relative RMSE away from emitters
    Rgb ratio_away{1.0};     // mean_ratio away from emitters, per channel
    size_t away_pixels = 0;  // pixels away from emitters
    size_t pixels = 0;       // all pixels
};

// `emitters`: the pixels that see an emitting face (Renderer::emitter_mask, same size).
ImageError image_error(const Image& a, const Image& ref, const PixelMask& emitters);

}  // namespace vlf
