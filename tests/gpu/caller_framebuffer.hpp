// A framebuffer the caller owns (an application's window, in the tests of GLDeformer::draw()):
// an RGBA8 texture of a size, bound on creation, deleted with the object. Needs a current GL
// context for its whole life.
#ifndef MULTICAGE_CALLER_FRAMEBUFFER_HPP
#define MULTICAGE_CALLER_FRAMEBUFFER_HPP

#include <epoxy/gl.h>

#include <opencv2/core.hpp>

namespace multicage_testing {

class CallerFramebuffer {
  public:
    explicit CallerFramebuffer(cv::Size size) {
        glGenTextures(1, &texture_);
        glBindTexture(GL_TEXTURE_2D, texture_);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, size.width, size.height);
        glGenFramebuffers(1, &fbo_);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_, 0);
    }
    ~CallerFramebuffer() {
        glDeleteFramebuffers(1, &fbo_);
        glDeleteTextures(1, &texture_);
    }
    CallerFramebuffer(const CallerFramebuffer&) = delete;
    CallerFramebuffer& operator=(const CallerFramebuffer&) = delete;

    bool complete() const {
        return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    }
    /** The rectangle (0, 0, size) of the bound framebuffer as RGB, in glReadPixels order
    (bottom row first). */
    static cv::Mat readRgb(cv::Size size) {
        cv::Mat got(size, CV_8UC3);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        glReadPixels(0, 0, size.width, size.height, GL_RGB, GL_UNSIGNED_BYTE, got.data);
        return got;
    }

  private:
    GLuint texture_ = 0, fbo_ = 0;
};

}  // namespace multicage_testing

#endif
