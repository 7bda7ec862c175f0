// The multicage: disjoint simple polygons over an image, plus the image frame (paper §3.1).
#ifndef OPENCV2_MULTICAGE_MULTICAGE_HPP
#define OPENCV2_MULTICAGE_MULTICAGE_HPP

#include <opencv2/core.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace cv {
namespace multicage {

enum CoordinateType {
    /** Whatever the multicage says (Multicage::coordinates(): a cage file's `coordinates:`,
    mean value when it names none). The default of bind() and DeformParams, so that one rule
    holds everywhere: the cage file's choice unless the caller names a type. */
    COORDINATES_FROM_CAGE = -1,
    MEAN_VALUE = 0,  //!< Hormann & Floater 2006; smooth, may be negative, global support
    HARMONIC = 1,    //!< DeRose & Meyer 2006; non-negative, each region sees only its polygons
    /** Mean value coordinates restricted, node by node, to the polygons that bound the node's
    region (the region inside a polygon and outside its children sees that polygon and its
    children; the frame's region sees the frame and the outlines): local as harmonic
    coordinates are, at the cost of mean value ones. What an innermost polygon holds follows
    that polygon alone, so a protected polygon moved by a similarity moves its content by
    exactly that similarity, whatever the outline and the frame do. Continuous across every
    edge (on an edge both sides give the edge's linear interpolation); partition of unity and
    linear precision hold. Not the paper's Algorithm 1: see docs/coordinates.md. */
    LOCAL_MEAN_VALUE = 2
};

/** The name of a CoordinateType in the CLI, Python and editor: "mvc", "harmonic", "local_mvc",
or "cage" for COORDINATES_FROM_CAGE; nullptr for any other value. */
CV_EXPORTS const char* coordinateTypeName(int type);
/** The words for a CoordinateType in sentences: "mean value", "harmonic", "local mean value". */
CV_EXPORTS const char* coordinateTypeDescription(int type);
/** The CoordinateType called name: "mvc" or "mean_value" (the cage file's spelling) for
MEAN_VALUE, "harmonic" for HARMONIC, "local_mvc" or "local_mean_value" for LOCAL_MEAN_VALUE.
False, type untouched, for any other name. */
CV_EXPORTS bool parseCoordinateType(const String& name, int& type);

/** Why name cannot be a pose name ("\"p \" starts or ends with a space"), or "" when it can.
A pose name is empty (an unnamed pose) or text a cage file keeps exactly, in YAML and JSON: no
control characters (bytes 0-31 and 127: tab, newline, ...), no space at its start or end (YAML drops
them), and no [ ] { } \ ' or " as its first character (cv::FileStorage's writer takes those for
structure or quoting). Multicage::addPose, setPose and the cage file reader refuse other names with
this reason. */
CV_EXPORTS std::string poseNameProblem(const std::string& name);

/** A pose: one position for every user vertex of a multicage, in vertex order.

A pose may be named and timed (keyframes for animation). The frame corners are not part of
a stored pose: they stay fixed.
*/
struct Pose {
    std::string name;
    double time = 0.0;               //!< seconds, for keyframed animation
    std::vector<Point2f> vertices;   //!< Multicage::vertexCount() points
};

/** A set of simple closed polygons over an image whose edges are pairwise disjoint.

Coordinates follow OpenCV: pixel (x, y) has its centre at the point (x, y), y grows down.
The image frame, the rectangle with corners (-0.5,-0.5) and (W-0.5,H-0.5), is always part of
the multicage as depth 0; it is not a user polygon. The depth of a user polygon is 1 + the
number of user polygons that contain it.

Orientation rule: the signed area A = 1/2 sum(x_i*y_{i+1} - x_{i+1}*y_i) is > 0 at even depth
and < 0 at odd depth (the paper's "outermost anti-clockwise, next clockwise" for y-down
coordinates). orient() applies it; binding works whatever the stored orientation is.

Vertex numbering: user polygons in order, each polygon's vertices in order, then the four
frame corners (top-left, top-right, bottom-right, bottom-left).

Multicage is a value type: copying copies the polygons and poses.
*/
class CV_EXPORTS_W Multicage {
public:
    Multicage();
    explicit Multicage(Size imageSize);

    /** Adds a polygon. points: std::vector<Point2f>, std::vector<Point>, or an Nx2 / Nx1
    two-channel matrix (CV_32F, CV_64F or CV_32S). Geometry is not checked here (see
    validate()), so that an editor can hold an invalid state. Existing poses get the new
    vertices at their rest positions. Returns the polygon's index. */
    int addPolygon(InputArray points);
    /** Replaces the rest positions of polygon i (same vertex count keeps the poses; another
    count resets the polygon's vertices in every pose to the new rest positions). */
    void setPolygon(int i, InputArray points);
    /** Removes polygon i and its vertices from every pose. */
    void removePolygon(int i);

    /** Applies the orientation rule: reverses every polygon whose signed area has the wrong
    sign for its depth, keeping vertex 0 first; poses are reordered the same way. */
    void orient();
    /** The largest image a multicage describes, in pixels: 2^30, the default limit of
    cv::imread (OPENCV_IO_MAX_IMAGE_PIXELS). Larger sizes would overflow the int pixel counts
    that OpenCV and the coefficient grids use. */
    static constexpr int64_t kMaxImagePixels = int64_t(1) << 30;

    /** Checks that the multicage can be bound: an image size of at least 2x2 and at most
    kMaxImagePixels pixels; every polygon with at
    least 3 finite vertices, no repeated consecutive vertex, a non-zero area, no
    self-intersection, strictly inside the image frame; no two polygons touching or crossing;
    the orientation rule; every pose with the right vertex count and finite positions.
    On failure returns false and, if why is given, one sentence naming the problem and where
    it is ("polygon 2 crosses polygon 0 at edge 3"). */
    bool validate(std::string* why = nullptr) const;
    /** As validate(), ignoring the orientation rule (binding does not need it). */
    bool validateGeometry(std::string* why = nullptr) const;

    Size imageSize() const;
    void setImageSize(Size size);
    int polygonCount() const;
    /** Number of user vertices (frame corners excluded). */
    int vertexCount() const;
    /** Rest positions of polygon i. */
    std::vector<Point2f> polygon(int i) const;
    /** Index in vertices() of polygon i's first vertex. */
    int polygonOffset(int i) const;
    /** 1 + the number of user polygons containing polygon i (the frame is depth 0). */
    int depth(int i) const;
    /** Signed area of polygon i (> 0: clockwise on screen). */
    double signedArea(int i) const;
    /** User vertices in order, then the 4 frame corners. */
    std::vector<Point2f> vertices() const;
    /** The 4 frame corners: (-0.5,-0.5), (W-0.5,-0.5), (W-0.5,H-0.5), (-0.5,H-0.5). */
    std::vector<Point2f> frame() const;

    /** Adds a named pose (vertexCount() points, or vertexCount()+4 with the frame corners
    last, which are dropped). Returns its index. A name poseNameProblem refuses throws. */
    int addPose(const std::string& name, InputArray vertices, double time = 0.0);
    void setPose(int i, const Pose& pose);
    void removePose(int i);
    int poseCount() const;
    const Pose& pose(int i) const;
    /** Index of the pose called name, or -1. */
    int findPose(const std::string& name) const;

    /** The cage coordinates this multicage is meant to be bound with (MEAN_VALUE, HARMONIC or
    LOCAL_MEAN_VALUE), saved in the cage file as
    `coordinates: mean_value|harmonic|local_mean_value`. */
    int coordinates() const;
    void setCoordinates(int coordinates);

    /** The multicage with its polygons moved to a pose (vertexCount() points, or +4 with the
    frame corners, which are ignored), for drawing a pose; poses are not copied. */
    Multicage posed(InputArray pose) const;

    /** The same multicage for an image of another size: every coordinate c becomes
    (c + 0.5) * newSize / imageSize - 0.5, so the frame maps onto the new frame. */
    Multicage scaled(Size newSize) const;

    /** Writes image_size, coordinates, polygons and poses (the cage file schema, docs/cli.md)
    into a cv::FileStorage; save() writes the same fields as standard YAML 1.2 or JSON. */
    void write(FileStorage& fs) const;
    /** Reads what write() writes. A malformed node throws a cv::Exception naming the field
    and the polygon or pose ("polygons[2]: odd number of coordinates (7)"). */
    void read(const FileNode& node);
    /** Loads a YAML or JSON cage file (the extension picks the format). */
    static Multicage load(const String& path);
    /** Saves to a YAML or JSON cage file, atomically: a reader never sees a partial file. */
    void save(const String& path) const;

    /** Draws the polygons, coloured by depth, on a BGR copy of image (for previews). */
    void draw(InputOutputArray image, int thickness = 1, bool drawVertices = true) const;

private:
    Size imageSize_;
    std::vector<std::vector<Point2f>> polygons_;
    std::vector<Pose> poses_;
    int coordinates_ = MEAN_VALUE;
};

/** Writes an image through a temporary file in the same folder and a rename, so that the
path holds either the old file or the complete new one. The extension picks the format. */
CV_EXPORTS void imwriteAtomic(const String& path, InputArray image,
                              const std::vector<int>& params = std::vector<int>());
/** Writes bytes to path atomically (temporary file, fsync, rename). */
CV_EXPORTS void writeFileAtomic(const String& path, const std::string& bytes);

}  // namespace multicage
}  // namespace cv

#endif
