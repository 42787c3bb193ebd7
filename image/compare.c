/* Image metrics: how far two renders are apart, as a viewer would see it.
 *
 * Colours are clamped to [0,1] first (like the PNG a user sees), so values
 * beyond white, -0.0 or +inf in both images compare equal; NaN counts as 0.
 * A pixel is "over 1/255" when any of its channels differs by more than one
 * 8-bit step. */
#include <math.h>
#include <stddef.h>

#include "rtt/image.h"

static double clamp01(float v)
{
    if (!(v > 0.0f))
        return 0.0;   /* also NaN */
    return v >= 1.0f ? 1.0 : (double)v;
}

bool rtt_image_compare(const rtt_image *a, const rtt_image *b, rtt_image_metrics *out, rtt_error *err)
{
    if (a->width != b->width || a->height != b->height)
        return rtt_error_set(err, "images differ in size (%ux%u vs %ux%u)", a->width, a->height, b->width,
                             b->height);
    size_t pixels = (size_t)a->width * a->height;
    double squared = 0.0, max_error = 0.0;
    uint64_t over = 0;
    for (size_t p = 0; p < pixels; p++) {
        bool pixel_over = false;
        for (size_t k = 0; k < 3; k++) {
            double diff = fabs(clamp01(a->rgb[p * 3 + k]) - clamp01(b->rgb[p * 3 + k]));
            squared += diff * diff;
            if (diff > max_error)
                max_error = diff;
            if (diff > 1.0 / 255.0)
                pixel_over = true;
        }
        over += pixel_over;
    }
    *out = (rtt_image_metrics){
        .rmse = pixels ? sqrt(squared / (double)(pixels * 3)) : 0.0,
        .max_error = max_error,
        .share_over_1_255 = pixels ? (double)over / (double)pixels : 0.0,
        .pixels_over_1_255 = over,
    };
    return true;
}
