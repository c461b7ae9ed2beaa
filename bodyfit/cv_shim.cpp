// The C face of OpenCV for bodyfit (cv_shim.h). Nothing here throws into C: every call is
// wrapped and OpenCV's exception text is returned in err.
#include "cv_shim.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <vector>

namespace
{

int fail(const char *what, const cv::Exception &e, char *err, size_t errlen)
{
    if (err && errlen)
        std::snprintf(err, errlen, "%s: OpenCV: %s", what, e.what());
    return -1;
}

// One thread for OpenCV: the images are 320x240 and the pipeline's four processes share two
// cores, so a parallel_for's worker threads (TBB here) only add their start, wait and yield to
// every call (docs/bodyfit.md, "CPU a frame in the pipeline"). Set once, before the first call.
void single_thread()
{
    static const bool done = [] {
        cv::setNumThreads(0);
        return true;
    }();
    (void)done;
}

} // namespace

extern "C" int cvs_depth_edges(const float *depth_m, int width, int height, float jump_m,
                               uint8_t *out, char *err, size_t errlen)
{
    single_thread();
    try {
        // Two passes of OpenCV (the 3x3 max and min) and two plain loops: a missing reading
        // must not count as near (for the max: 0 is below every reading) nor as far (for the
        // min: it becomes 1e6). The masks and differences as whole images cost 9 passes more.
        const size_t n = (size_t)width * (size_t)height;
        cv::Mat d(height, width, CV_32F, const_cast<float *>(depth_m));
        cv::Mat for_min(height, width, CV_32F);
        float *fm = for_min.ptr<float>();
        for (size_t i = 0; i < n; ++i)
            fm[i] = depth_m[i] > 0.0f ? depth_m[i] : 1e6f;
        cv::Mat hi, lo;
        cv::Mat k = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3));
        cv::dilate(d, hi, k);
        cv::erode(for_min, lo, k);
        const float *h = hi.ptr<float>(), *l = lo.ptr<float>();
        for (size_t i = 0; i < n; ++i)
            out[i] = depth_m[i] > 0.0f && h[i] - l[i] > jump_m;
        return 0;
    } catch (const cv::Exception &e) {
        return fail("cvs_depth_edges", e, err, errlen);
    }
}

extern "C" int cvs_components(const uint8_t *mask, int width, int height, int32_t *labels,
                              cvs_component *comps, int max_comps, int *count, char *err,
                              size_t errlen)
{
    single_thread();
    try {
        cv::Mat m(height, width, CV_8U, const_cast<uint8_t *>(mask));
        cv::Mat lab(height, width, CV_32S, labels), stats, centroids;
        int n = cv::connectedComponentsWithStats(m, lab, stats, centroids, 8, CV_32S);
        int c = 0;
        for (int i = 1; i < n && c < max_comps; ++i, ++c) {
            comps[c].area = stats.at<int>(i, cv::CC_STAT_AREA);
            comps[c].x0 = stats.at<int>(i, cv::CC_STAT_LEFT);
            comps[c].y0 = stats.at<int>(i, cv::CC_STAT_TOP);
            comps[c].x1 = comps[c].x0 + stats.at<int>(i, cv::CC_STAT_WIDTH) - 1;
            comps[c].y1 = comps[c].y0 + stats.at<int>(i, cv::CC_STAT_HEIGHT) - 1;
        }
        *count = c;
        return 0;
    } catch (const cv::Exception &e) {
        return fail("cvs_components", e, err, errlen);
    }
}

extern "C" int cvs_dilate(const uint8_t *mask, int width, int height, int radius, uint8_t *out,
                          char *err, size_t errlen)
{
    single_thread();
    try {
        cv::Mat m(height, width, CV_8U, const_cast<uint8_t *>(mask)), o(height, width, CV_8U, out);
        cv::Mat k =
            cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * radius + 1, 2 * radius + 1));
        cv::dilate(m != 0, o, k);
        o.setTo(1, o);
        return 0;
    } catch (const cv::Exception &e) {
        return fail("cvs_dilate", e, err, errlen);
    }
}

extern "C" int cvs_nearest_set(const uint8_t *mask, int width, int height, int margin,
                               int32_t *nearest, int roi[4], char *err, size_t errlen)
{
    single_thread();
    try {
        cv::Mat m(height, width, CV_8U, const_cast<uint8_t *>(mask));
        std::fill(nearest, nearest + (size_t)width * height, -1);
        cv::Rect box = cv::boundingRect(m);
        roi[0] = roi[1] = 0;
        roi[2] = roi[3] = -1;
        if (box.area() == 0)
            return 0;
        box.x -= margin, box.y -= margin, box.width += 2 * margin, box.height += 2 * margin;
        box &= cv::Rect(0, 0, width, height);
        roi[0] = box.x, roi[1] = box.y, roi[2] = box.x + box.width - 1;
        roi[3] = box.y + box.height - 1;
        // distanceTransform measures to the nearest zero pixel: invert the mask.
        cv::Mat inv = (m(box) == 0);
        cv::Mat dist, lab;
        cv::distanceTransform(inv, dist, lab, cv::DIST_L2, cv::DIST_MASK_5, cv::DIST_LABEL_PIXEL);
        // Labels number the zero pixels of inv (the set pixels of m) in scan order of the box.
        std::vector<int32_t> where(1, -1);
        for (int y = 0; y < box.height; ++y)
            for (int x = 0; x < box.width; ++x)
                if (mask[(size_t)(y + box.y) * width + x + box.x])
                    where.push_back((y + box.y) * width + x + box.x);
        for (int y = 0; y < box.height; ++y) {
            const int *l = lab.ptr<int>(y);
            int32_t *o = nearest + (size_t)(y + box.y) * width + box.x;
            for (int x = 0; x < box.width; ++x)
                o[x] = (l[x] > 0 && l[x] < (int)where.size()) ? where[(size_t)l[x]] : -1;
        }
        return 0;
    } catch (const cv::Exception &e) {
        return fail("cvs_nearest_set", e, err, errlen);
    }
}
