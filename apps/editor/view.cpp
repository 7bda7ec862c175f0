#include <epoxy/gl.h>
// GLFW after epoxy: epoxy must be the one GL header.
#include <GLFW/glfw3.h>

#include <opencv2/imgproc.hpp>
#include <opencv2/multicage.hpp>

#include "actions.hpp"
#include "resize_mode.hpp"
#include "view.hpp"

namespace multicage_editor {

void uploadImageTexture(View& v, const cv::Mat& rgba) {
    CV_Assert(rgba.type() == CV_8UC4 && rgba.isContinuous());
    if (!v.imageTexture) glGenTextures(1, &v.imageTexture);
    glBindTexture(GL_TEXTURE_2D, v.imageTexture);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, rgba.cols, rgba.rows, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 rgba.data);
}

cv::Mat displayImage(const cv::Mat& image) {
    cv::Mat eight = image, rgba;
    if (image.depth() == CV_16U) image.convertTo(eight, CV_8U, 1.0 / 257);
    if (image.depth() == CV_32F) image.convertTo(eight, CV_8U, 255.0);
    if (eight.channels() == 1)
        cv::cvtColor(eight, rgba, cv::COLOR_GRAY2RGBA);
    else if (eight.channels() == 3)
        cv::cvtColor(eight, rgba, cv::COLOR_BGR2RGBA);
    else
        cv::cvtColor(eight, rgba, cv::COLOR_BGRA2RGBA);
    return rgba;
}

void screenshot(GLFWwindow* window, const std::string& path) {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window, &w, &h);
    cv::Mat rgba(h, w, CV_8UC4), bgr;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data);
    cv::flip(rgba, rgba, 0);  // glReadPixels returns the bottom row first
    cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
    mc::imwriteAtomic(path, bgr);
}

void updateDeformation(Editor& e, View& v, const Settings& s) {
    if (e.image.empty() || e.mode == Mode::Rest) return;
    const bool restChanged = !samePolygons(v.boundRest, e.shown.cage) ||
                             v.boundCoords != s.coordinates || v.boundStep != s.gridStep;
    if (restChanged || !v.deformer) {
        try {
            const auto t0 = Clock::now();
            v.deformer.reset();
            v.binding = mc::bind(e.shown.cage, s.coordinates, s.gridStep);
            v.deformer.reset(new mc::GLDeformer(displayImage(e.image), v.binding));
            v.bindMs = msSince(t0);
            ++v.bindings;
            v.restNodes = v.binding.nodes();
            v.error.clear();
        } catch (const std::exception& ex) {
            v.error = ex.what();
            v.deformer.reset();
        }
        v.boundRest = e.shown.cage;
        v.boundCoords = s.coordinates;
        v.boundStep = s.gridStep;
        v.rendered = false;
    }
    if (!v.deformer) return;
    // Resize mode: the resize pose, whose frame on the new frame makes the GLDeformer render
    // the new size.
    if (e.mode == Mode::Resize && !resizePoseFor(e, v)) return;
    const std::vector<cv::Point2f>& pose = e.mode == Mode::Resize ? v.resizePose : e.shown.pose;
    if (v.rendered && v.renderedPose == pose) return;
    const auto t0 = Clock::now();
    v.deformer->setPose(pose);
    v.deformer->render(cv::Scalar(40, 40, 40, 255));
    if (v.finishForTiming) v.deformer->finish();
    v.renderMs = msSince(t0);
    const auto t1 = Clock::now();
    v.renderedPose = pose;
    v.rendered = true;
    cv::Mat positions;
    v.binding.apply(pose, positions);
    v.folded = mc::countFoldedTriangles(positions, v.restNodes);
    v.foldMs = msSince(t1);
}

}  // namespace multicage_editor
