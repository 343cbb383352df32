/* vergence — dense optical flow through OpenCV's DIS (flow.h), the one C++
 * file of engine/flow. OpenCV (Debian's libopencv-video 4.6) computes; the
 * sizes are checked here first, and no exception leaves this file: an
 * OpenCV error is one line and a status. */
#include <cstdio>
#include <cstring>
#include <new>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

extern "C" {
#include "core/log.h"
#include "flow.h"
}

namespace {

/* An image as 8-bit grey; a view of the pixels when they are grey already. */
cv::Mat grey(const flow_image *img)
{
    cv::Mat m(img->height, img->width, CV_MAKETYPE(CV_8U, img->channels), const_cast<uint8_t *>(img->pixels));
    if (img->channels == 1)
        return m;
    cv::Mat out;
    cv::cvtColor(m, out, img->channels == 3 ? cv::COLOR_RGB2GRAY : cv::COLOR_RGBA2GRAY);
    return out;
}

int cv_preset(flow_preset p)
{
    switch (p) {
    case FLOW_PRESET_FAST: return cv::DISOpticalFlow::PRESET_FAST;
    case FLOW_PRESET_ULTRAFAST: return cv::DISOpticalFlow::PRESET_ULTRAFAST;
    default: return cv::DISOpticalFlow::PRESET_MEDIUM; /* FINE: MEDIUM down to full resolution */
    }
}

bool check(const flow_image *img, const char *which, const char *what)
{
    if (!img || !img->pixels) {
        vg_error("flow of %s: the %s image has no pixels", what, which);
        return false;
    }
    if (img->channels != 1 && img->channels != 3 && img->channels != 4) {
        vg_error("flow of %s: the %s image has %d channels (1 grey, 3 RGB or 4 RGBA)", what, which, img->channels);
        return false;
    }
    if (img->width < FLOW_MIN_SIDE || img->height < FLOW_MIN_SIDE || img->width > 65536 || img->height > 65536) {
        vg_error("flow of %s: the %s image is %dx%d; the flow needs %d to 65536 pixels a side", what, which,
                 img->width, img->height, FLOW_MIN_SIDE);
        return false;
    }
    return true;
}

/* One direction into out (width x height x 2 floats, packed). DIS takes a
 * flow array that already has the images' size and type as its initial
 * flow (OpenCV 4.6, dis_flow.cpp: use_input_flow), and NaN there makes it
 * read out of bounds: it gets an empty array, and the result is copied. */
void calc(cv::DISOpticalFlow &dis, const cv::Mat &from, const cv::Mat &to, float *out)
{
    cv::Mat flow;
    dis.calc(from, to, flow);
    CV_Assert(flow.type() == CV_32FC2 && flow.rows == from.rows && flow.cols == from.cols);
    flow.copyTo(cv::Mat(from.rows, from.cols, CV_32FC2, out));
}

} // namespace

extern "C" const char *flow_preset_name(flow_preset p)
{
    switch (p) {
    case FLOW_PRESET_MEDIUM: return "medium";
    case FLOW_PRESET_FAST: return "fast";
    case FLOW_PRESET_ULTRAFAST: return "ultrafast";
    default: return "fine";
    }
}

extern "C" void flow_set_threads(int n)
{
    try {
        cv::setNumThreads(n > 0 ? n : -1);
    } catch (...) {
    }
}

extern "C" vg_status flow_dis(const flow_image *a, const flow_image *b, flow_preset preset, const char *what,
                              float *fwd, float *bwd)
{
    if (!what)
        what = "two images";
    if (!check(a, "first", what) || !check(b, "second", what))
        return VG_ERR_ARG;
    if (a->width != b->width || a->height != b->height) {
        vg_error("flow of %s: the images are %dx%d and %dx%d (the flow needs one size)", what, a->width, a->height,
                 b->width, b->height);
        return VG_ERR_ARG;
    }
    if (!fwd) {
        vg_error("flow of %s: no buffer for the flow", what);
        return VG_ERR_ARG;
    }
    try {
        cv::Mat ga = grey(a), gb = grey(b);
        cv::Ptr<cv::DISOpticalFlow> dis = cv::DISOpticalFlow::create(cv_preset(preset));
        if (preset == FLOW_PRESET_FINE)
            dis->setFinestScale(0);
        calc(*dis, ga, gb, fwd);
        if (bwd)
            calc(*dis, gb, ga, bwd);
    } catch (const cv::Exception &e) {
        vg_error("flow of %s: OpenCV's DIS failed: %s", what, e.what());
        return VG_ERR_UNSUPPORTED;
    } catch (const std::bad_alloc &) {
        vg_error("flow of %s: out of memory for %dx%d images", what, a->width, a->height);
        return VG_ERR_NOMEM;
    } catch (...) {
        vg_error("flow of %s: OpenCV's DIS failed", what);
        return VG_ERR_UNSUPPORTED;
    }
    return VG_OK;
}
