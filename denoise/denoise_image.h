#pragma once
// A rendered EXR's channels ↔ the denoiser's buffers (denoise/denoise.h): what `sylva denoise` and
// `sylva render --denoise` run. The beauty channels are those with half-buffers (`even.<C>`): the
// visible band's R, G, B and every other band's channels, denoised in one pass.

#include "core/image.h"
#include "denoise/denoise.h"

#include <string>
#include <vector>

namespace sylva {

// What the header records of a denoised image (attribute "sylva:denoised").
inline constexpr const char* kDenoiserName = "sylva-nfor 2 (docs/denoise.md)";

// The beauty channels of `image` that can be denoised: every C with even.<C>, odd.<C> and var.<C>.
std::vector<std::string> denoisable_channels(const Image& image);

// The buffers of `image`'s denoisable channels. Throws sylva::Error naming what is missing (no
// half-buffers or features: the render was made without --features), or an image already denoised.
DenoiseBuffers denoise_buffers(const Image& image);

// `image` with each denoisable channel C replaced by its denoised values and the noisy ones kept as
// noisy.<C>; every other channel as it was. The header records the denoiser (kDenoiserName) and
// its settings. Throws as denoise_buffers.
Image denoise_image(const Image& image, const DenoiseSettings& settings = {}, DenoiseStats* stats = nullptr);

}  // namespace sylva
