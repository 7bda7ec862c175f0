// multicage pose CAGE.yml --name NAME OPERATIONS... -o OUT.yml: a pose made from moves of
// polygons and vertices, for scripts (the editor needs a display).
#include <cmath>
#include <iostream>
#include <map>
#include <opencv2/imgproc.hpp>

#include "cli_util.hpp"

namespace multicage_cli {

namespace {
using Values = std::vector<std::vector<std::string>>;  // one inner list per occurrence

struct PoseOptions {
    std::string cage, output, name, from;
    double time = std::nan("");
    bool replace = false, allowInvalid = false;
    Values translate, scale, stretch, rotate, about, moveVertex;
};

// What an operation acts on: vertex indices into the pose (Multicage::vertices() order).
struct Target {
    std::vector<int> vertices;
    cv::Point2f centre;  // what --scale, --stretch and --rotate turn about without --about
};

double number(const std::string& flag, const std::string& text) {
    size_t used = 0;
    double v = std::nan("");
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
    }
    if (used != text.size() || !std::isfinite(v))
        throw UsageError(flag + ": '" + text + "' is not a finite number");
    return v;
}

// `what` names the index in the message: "polygon %s", "vertex %s of polygon 2".
int index(const std::string& flag, const std::string& text, int count, const std::string& what) {
    const double v = number(flag, text);
    if (v != std::floor(v) || v < 0 || v >= count)
        throw UsageError(flag + ": " + cv::format(what.c_str(), text.c_str()) +
                         " is out of range: 0 to " + std::to_string(count - 1));
    return static_cast<int>(v);
}

// P (polygon P), P+ (polygon P and every polygon inside it), P:V (vertex V of polygon P) or all.
Target target(const std::string& flag, const std::string& text,
              const cv::multicage::Multicage& cage, const std::vector<cv::Point2f>& pose) {
    std::vector<int> first(cage.polygonCount() + 1, 0);  // first vertex of each polygon
    for (int p = 0; p < cage.polygonCount(); ++p)
        first[p + 1] = first[p] + static_cast<int>(cage.polygon(p).size());
    auto polygonAt = [&](int p) {
        return std::vector<cv::Point2f>(pose.begin() + first[p], pose.begin() + first[p + 1]);
    };
    auto centroid = [](const std::vector<cv::Point2f>& points) {
        const cv::Moments m = cv::moments(points);
        if (std::abs(m.m00) < 1e-9) return cv::Point2f(cv::mean(points)[0], cv::mean(points)[1]);
        return cv::Point2f(float(m.m10 / m.m00), float(m.m01 / m.m00));
    };
    Target t;
    if (text == "all") {
        t.vertices.resize(cage.vertexCount());
        for (int i = 0; i < cage.vertexCount(); ++i) t.vertices[i] = i;
        const cv::Size size = cage.imageSize();
        t.centre = cv::Point2f((size.width - 1) / 2.f, (size.height - 1) / 2.f);
        return t;
    }
    const size_t colon = text.find(':');
    const bool nested = colon == std::string::npos && !text.empty() && text.back() == '+';
    const std::string polygonText =
        text.substr(0, colon == std::string::npos ? text.size() - nested : colon);
    if (polygonText.empty() || polygonText.find_first_not_of("0123456789") != std::string::npos)
        throw UsageError(flag + ": '" + text +
                         "' is not a target: P (polygon P), P+ (polygon P and "
                         "the polygons inside it), P:V (vertex V of polygon P) or all");
    const int p = index(flag, polygonText, cage.polygonCount(), "polygon %s");
    if (colon != std::string::npos) {
        const int v = index(flag, text.substr(colon + 1), first[p + 1] - first[p],
                            "vertex %s of polygon " + polygonText);
        t.vertices = {first[p] + v};
        t.centre = pose[first[p] + v];
        return t;
    }
    const std::vector<cv::Point2f> outline = cage.polygon(p);  // nesting as at rest
    for (int q = 0; q < cage.polygonCount(); ++q) {
        if (q != p && !(nested && cv::pointPolygonTest(outline, cage.polygon(q)[0], false) > 0))
            continue;
        for (int i = first[q]; i < first[q + 1]; ++i) t.vertices.push_back(i);
    }
    t.centre = centroid(polygonAt(p));
    return t;
}

void runPose(const PoseOptions& o,
             const std::vector<std::pair<std::string, std::vector<std::string>>>& ops) {
    using namespace cv::multicage;
    Multicage cage = loadCage(o.cage, cv::Size());
    if (o.name.empty()) throw UsageError("--name: a pose needs a name");
    const std::string problem = poseNameProblem(o.name);
    if (!problem.empty())
        throw UsageError("--name: " + problem + " (a cage file could not keep it)");
    std::vector<cv::Point2f> pose = cage.vertices();
    pose.resize(cage.vertexCount());
    double time = o.time;
    if (!o.from.empty()) {
        const int from = cage.findPose(o.from);
        if (from < 0) throw UsageError("--from: " + o.cage + " has no pose named '" + o.from + "'");
        pose = cage.pose(from).vertices;
    }
    const int existing = cage.findPose(o.name);
    if (existing >= 0 && !o.replace)
        throw UsageError("--name: " + o.cage + " already has a pose named '" + o.name +
                         "' (add --replace to overwrite it, or choose another name)");
    if (std::isnan(time)) {  // a new keyframe after the others; a replaced pose keeps its time
        time = existing >= 0 ? cage.pose(existing).time : 0.0;
        if (existing < 0)
            for (int i = 0; i < cage.poseCount(); ++i)
                time = std::max(time, std::floor(cage.pose(i).time) + 1);
    }
    if (ops.empty())
        throw UsageError(
            "no operation: add --translate, --scale, --stretch, --rotate or --move-vertex");

    const std::vector<cv::Point2f> start = pose;
    bool haveAbout = false;
    cv::Point2f about;
    for (const auto& [flag, v] : ops) {
        if (flag == "--about") {
            about = cv::Point2f(float(number(flag, v[0])), float(number(flag, v[1])));
            haveAbout = true;
            continue;
        }
        const Target t = target(flag, v[0], cage, pose);
        const cv::Point2f c = haveAbout ? about : t.centre;
        haveAbout = false;  // --about applies to the next operation only
        if (flag == "--translate") {
            const cv::Point2f d(float(number(flag, v[1])), float(number(flag, v[2])));
            for (int i : t.vertices) pose[i] += d;
        } else if (flag == "--scale" || flag == "--stretch") {
            const double sx = number(flag, v[1]), sy = flag == "--scale" ? sx : number(flag, v[2]);
            for (int i : t.vertices)
                pose[i] = cv::Point2f(float(c.x + (pose[i].x - c.x) * sx),
                                      float(c.y + (pose[i].y - c.y) * sy));
        } else if (flag == "--rotate") {
            // Counter-clockwise on screen for positive degrees, as cv::getRotationMatrix2D.
            const double a = number(flag, v[1]) * CV_PI / 180, cs = std::cos(a), sn = std::sin(a);
            for (int i : t.vertices) {
                const double x = pose[i].x - c.x, y = pose[i].y - c.y;
                pose[i] = cv::Point2f(float(c.x + cs * x + sn * y), float(c.y - sn * x + cs * y));
            }
        } else if (flag == "--move-vertex") {
            if (t.vertices.size() != 1)
                throw UsageError("--move-vertex: '" + v[0] +
                                 "' is not one vertex (write P:V, e.g. 0:3)");
            pose[t.vertices[0]] = cv::Point2f(float(number(flag, v[1])), float(number(flag, v[2])));
        }
    }
    if (haveAbout)
        throw UsageError("--about: comes before the --scale, --stretch or --rotate it centres");

    Pose made{o.name, time, pose};
    if (existing >= 0)
        cage.setPose(existing, made);
    else
        cage.addPose(made.name, made.vertices, made.time);
    const int at = existing >= 0 ? existing : cage.poseCount() - 1;
    checkPose("pose", o.cage, cage, at, o.allowInvalid);
    const std::string output = o.output.empty() ? o.cage : o.output;
    cage.save(output);
    int moved = 0;
    double most = 0;
    for (size_t i = 0; i < pose.size(); ++i) {
        const double d = cv::norm(pose[i] - start[i]);
        moved += d > 0;
        most = std::max(most, d);
    }
    std::cout << "wrote " << output << " (pose '" << o.name << "' at " << time << " s, "
              << (existing >= 0 ? "replaced" : "added") << "; "
              << plural(long(ops.size()), "operation") << " moved " << moved << " of "
              << plural(long(pose.size()), "vertex", "vertices") << ", up to "
              << cv::format("%.1f", most) << " px; " << plural(cage.poseCount(), "pose")
              << " in the file)" << std::endl;
}
}  // namespace

void addPoseCommand(CLI::App& app) {
    auto o = std::make_shared<PoseOptions>();
    CLI::App* cmd = app.add_subcommand(
        "pose",
        "Make a pose of CAGE.yml from moves of its polygons and vertices, check it, and write it "
        "into the cage file (CAGE itself, or -o OUT) (a pose for `multicage deform --pose NAME` or "
        "a keyframe for "
        "`multicage animate`, without the editor).\n"
        "Operations run in the order given, starting from the rest polygons (or --from POSE). "
        "TARGET is P (polygon P, counted from 0 in the file's order), P+ (polygon P and every "
        "polygon inside it, as an object with its face), P:V (vertex V of polygon P) or all. "
        "--scale, --stretch and --rotate turn about the target's centre (a polygon's centroid, "
        "a vertex itself, the image centre for all), or about the point of an --about just "
        "before them. A pose whose polygons cross, leave the frame or change nesting is refused "
        "with the polygons named.\n"
        "Examples:\n"
        "  multicage pose cage.yml --name wide --stretch 0 1.3 1 -o posed.yml\n"
        "  multicage pose cage.yml --name nod --rotate 1+ -10 --translate 1+ 0 8 -o posed.yml\n"
        "  multicage pose cage.yml --name tip --move-vertex 0:3 250 40 --time 0.5   (into "
        "cage.yml)");
    cmd->add_option("CAGE", o->cage, "Cage file (.yml, .yaml or .json)")->required();
    cmd->add_option("-o,--output", o->output,
                    "Cage file to write, only when the pose is valid (default: CAGE itself, "
                    "rewritten atomically; comments in it are not kept)");
    cmd->add_option("--name", o->name, "Name of the pose")->required();
    cmd->add_option("--from", o->from, "Start from this pose instead of the rest polygons");
    cmd->add_option("--time", o->time,
                    "Keyframe time in seconds (default: a replaced pose keeps its own; a new one "
                    "comes a second after the last whole second of the others)")
        ->check(CLI::Range(-1e9, 1e9));
    cmd->add_flag("--replace", o->replace, "Overwrite a pose of the same name");
    addAllowInvalidFlag(cmd, o->allowInvalid, "Write");
    auto op = [&](const char* flag, Values& values, int count, const char* names,
                  const char* help) {
        cmd->add_option(flag, values, help)
            ->type_name(names)
            ->expected(count)
            ->allow_extra_args(false)
            ->group("Operations");
    };
    op("--translate", o->translate, 3, "TARGET DX DY",
       "Move TARGET by (DX, DY) pixels (y points down)");
    op("--scale", o->scale, 2, "TARGET S", "Scale TARGET by S about its centre");
    op("--stretch", o->stretch, 3, "TARGET SX SY", "Scale TARGET by SX across and SY down");
    op("--rotate", o->rotate, 2, "TARGET DEGREES",
       "Turn TARGET by DEGREES, counter-clockwise on screen for positive values");
    op("--move-vertex", o->moveVertex, 3, "P:V X Y", "Put vertex V of polygon P at (X, Y)");
    op("--about", o->about, 2, "X Y", "The centre of the next --scale, --stretch or --rotate");
    cmd->callback([o, cmd] {
        // CLI11 lists one entry per value parsed, in command-line order: regroup them into the
        // operations as typed, each option's occurrences taken in turn.
        const std::map<std::string, Values*> lists = {
            {"--translate", &o->translate},    {"--scale", &o->scale},
            {"--stretch", &o->stretch},        {"--rotate", &o->rotate},
            {"--move-vertex", &o->moveVertex}, {"--about", &o->about}};
        std::map<std::string, size_t> taken;
        std::vector<std::pair<std::string, std::vector<std::string>>> ops;
        const std::vector<CLI::Option*> order = cmd->parse_order();
        for (size_t i = 0; i < order.size();) {
            const auto it = lists.find(order[i]->get_name());
            if (it == lists.end()) {
                ++i;
                continue;
            }
            const std::vector<std::string>& values = (*it->second)[taken[it->first]++];
            ops.emplace_back(it->first, values);
            i += values.size();
        }
        runPose(*o, ops);
    });
}

}  // namespace multicage_cli
