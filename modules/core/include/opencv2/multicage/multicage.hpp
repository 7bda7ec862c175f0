/** @file
@brief The multicage: disjoint simple polygons over an image, plus the image frame (paper §3.1).
@ingroup multicage_core
*/
#ifndef OPENCV2_MULTICAGE_MULTICAGE_HPP
#define OPENCV2_MULTICAGE_MULTICAGE_HPP

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace cv {
namespace multicage {

//! @addtogroup multicage_core
//! @{

/** @brief Which cage coordinates bind a multicage: bind(), DeformParams::coordinates,
Multicage::coordinates() and the cage file's `coordinates:`.

@sa resolveCoordinates, coordinateTypeName, parseCoordinateType, docs/coordinates.md
*/
enum CoordinateType {
    /** Whatever the multicage says (Multicage::coordinates(): a cage file's `coordinates:`,
    mean value when it names none). The default of bind() and DeformParams, so that one rule
    holds everywhere: the cage file's choice unless the caller names a type. */
    COORDINATES_FROM_CAGE = -1,
    /** Mean value coordinates (Floater 2003; Hormann & Floater 2006) summed over the whole
    multicage as in the paper's Algorithm 1: smooth, may be negative, global support. */
    MEAN_VALUE = 0,
    /** Harmonic coordinates (Joshi et al. 2007; DeRose & Meyer 2006): non-negative, each
    region sees only its polygons. */
    HARMONIC = 1,
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

/** @brief The name of a CoordinateType in the CLI, Python and editor.

@param type a CoordinateType.
@return "mvc", "harmonic", "local_mvc", or "cage" for COORDINATES_FROM_CAGE; nullptr for any
other value.
@sa parseCoordinateType, coordinateTypeDescription
*/
CV_EXPORTS const char* coordinateTypeName(int type);
/** @brief The words for a CoordinateType in sentences.

@param type a CoordinateType.
@return "mean value", "harmonic" or "local mean value"; "the cage's" for
COORDINATES_FROM_CAGE and any other value.
@sa coordinateTypeName
*/
CV_EXPORTS const char* coordinateTypeDescription(int type);
/** @brief The CoordinateType called name.

@param name "mvc" or "mean_value" (the cage file's spelling) for MEAN_VALUE, "harmonic" for
HARMONIC, "local_mvc" or "local_mean_value" for LOCAL_MEAN_VALUE.
@param[out] type receives the CoordinateType; untouched when the name is unknown.
@return false, type untouched, for any other name.
@sa coordinateTypeName
*/
CV_EXPORTS bool parseCoordinateType(const String& name, int& type);

/** @brief Why name cannot be a pose name, or "" when it can.

A pose name is empty (an unnamed pose) or text a cage file keeps exactly, in YAML and JSON: no
control characters (bytes 0-31 and 127: tab, newline, ...), no space at its start or end (YAML
drops them), and no bracket, brace, backslash or quote (`[ ] { } \ '` or a double quote) as
its first character (cv::FileStorage's writer takes those for structure or quoting).
Multicage::addPose, Multicage::setPose and the cage file reader refuse other names with this
reason.

@param name the proposed pose name.
@return one phrase naming the problem (`"p " starts or ends with a space`), or "" when the
name can be kept.
*/
CV_EXPORTS std::string poseNameProblem(const std::string& name);

/** @brief A pose: one position for every user vertex of a multicage, in vertex order.

A pose may be named and timed (keyframes for animation). The frame corners are not part of
a stored pose: they stay fixed.
@sa Multicage::addPose, samplePose
*/
struct Pose {
    std::string name;               //!< the pose's name ("" for an unnamed one; poseNameProblem())
    double time = 0.0;              //!< seconds, for keyframed animation
    std::vector<Point2f> vertices;  //!< Multicage::vertexCount() points
};

/** @brief A set of simple closed polygons over an image whose edges are pairwise disjoint.

Coordinates follow OpenCV: pixel (x, y) has its centre at the point (x, y), y grows down.
The image frame, the rectangle with corners (-0.5,-0.5) and (W-0.5,H-0.5), is always part of
the multicage as depth 0; it is not a user polygon. The depth of a user polygon is 1 + the
number of user polygons that contain it.

Orientation rule: the signed area `A = 1/2 sum(x_i*y_{i+1} - x_{i+1}*y_i)` is > 0 at even
depth and < 0 at odd depth (the paper's "outermost anti-clockwise, next clockwise" for y-down
coordinates), so that the raw mean value weights of the polygons bounding a region agree in
sign there and never cancel ("spring up"). orient() applies it; binding works whatever the
stored orientation is.

Vertex numbering: user polygons in order, each polygon's vertices in order, then the four
frame corners (top-left, top-right, bottom-right, bottom-left).

Multicage is a value type: copying copies the polygons and poses.
@sa bind, proposeMulticage, docs/cli.md (the cage file)
*/
class CV_EXPORTS_W Multicage {
  public:
    /** @brief An empty multicage: no polygon, no pose, image size 0x0 (set one with
    setImageSize() before validating or binding), MEAN_VALUE coordinates. */
    Multicage();
    /** @brief An empty multicage over an image of imageSize pixels.
    @param imageSize the image's width and height; the frame is its border. */
    explicit Multicage(Size imageSize);

    /** @brief Adds a polygon.

    Geometry is not checked here (see validate()), so that an editor can hold an invalid
    state. Existing poses get the new vertices at their rest positions.
    @param points std::vector<Point2f>, std::vector<Point>, or an Nx2 / Nx1 two-channel matrix
    (CV_32F, CV_64F or CV_32S); another depth or shape throws a cv::Exception.
    @return the polygon's index.
    */
    int addPolygon(InputArray points);
    /** @brief Replaces the rest positions of polygon i.

    The same vertex count keeps the poses; another count resets the polygon's vertices in
    every pose to the new rest positions.
    @param i a polygon index, 0 <= i < polygonCount().
    @param points as addPolygon().
    */
    void setPolygon(int i, InputArray points);
    /** @brief Removes polygon i and its vertices from every pose.
    @param i a polygon index, 0 <= i < polygonCount(). */
    void removePolygon(int i);

    /** @brief Applies the orientation rule: reverses every polygon whose signed area has the
    wrong sign for its depth, keeping vertex 0 first; poses are reordered the same way. */
    void orient();
    /** @brief The largest image a multicage describes, in pixels: 2^30, the default limit of
    cv::imread (OPENCV_IO_MAX_IMAGE_PIXELS). Larger sizes would overflow the int pixel counts
    that OpenCV and the coefficient grids use. */
    static constexpr int64_t kMaxImagePixels = int64_t(1) << 30;

    /** @brief Checks that the multicage can be bound and follows the orientation rule.

    Checked: an image size of at least 2x2 and at most kMaxImagePixels pixels; every polygon
    with at least 3 finite vertices, no repeated consecutive vertex, a non-zero area, no
    self-intersection, strictly inside the image frame; no two polygons touching or crossing;
    the orientation rule; every pose with the right vertex count and finite positions.
    @param[out] why when not null, receives on failure one sentence naming the problem and
    where it is ("polygon 2 crosses polygon 0 at edge 3").
    @return true when every check passes.
    @sa validateGeometry, validatePose
    */
    bool validate(std::string* why = nullptr) const;
    /** @brief As validate(), ignoring the orientation rule (binding does not need it).
    @param[out] why as validate().
    @return true when every check but the orientation rule passes. */
    bool validateGeometry(std::string* why = nullptr) const;

    /** @brief The size of the image the multicage is drawn on.
    @return its width and height in pixels. */
    Size imageSize() const;
    /** @brief Sets the image size (the frame) without moving the polygons (scaled() moves them).
    @param size the new width and height in pixels. */
    void setImageSize(Size size);
    /** @brief Number of user polygons (the frame excluded).
    @return the count. */
    int polygonCount() const;
    /** @brief Number of user vertices (frame corners excluded).
    @return the sum of the polygons' vertex counts. */
    int vertexCount() const;
    /** @brief Rest positions of polygon i.
    @param i a polygon index, 0 <= i < polygonCount().
    @return its vertices in order. */
    std::vector<Point2f> polygon(int i) const;
    /** @brief Index in vertices() of polygon i's first vertex.
    @param i a polygon index, 0 <= i <= polygonCount() (polygonCount() gives vertexCount()).
    @return the offset. */
    int polygonOffset(int i) const;
    /** @brief 1 + the number of user polygons containing polygon i (the frame is depth 0).
    @param i a polygon index, 0 <= i < polygonCount().
    @return the depth, 1 for an outline. */
    int depth(int i) const;
    /** @brief Signed area of polygon i (> 0: clockwise on screen).
    @param i a polygon index, 0 <= i < polygonCount().
    @return `1/2 sum(x_k*y_{k+1} - x_{k+1}*y_k)` in square pixels. */
    double signedArea(int i) const;
    /** @brief User vertices in order, then the 4 frame corners.
    @return vertexCount() + 4 points. */
    std::vector<Point2f> vertices() const;
    /** @brief The 4 frame corners: (-0.5,-0.5), (W-0.5,-0.5), (W-0.5,H-0.5), (-0.5,H-0.5).
    @return the corners in that order. */
    std::vector<Point2f> frame() const;

    /** @brief Adds a named pose.
    @param name the pose's name; a name poseNameProblem() refuses throws a cv::Exception.
    @param vertices vertexCount() points, or vertexCount()+4 with the frame corners last, which
    are dropped (as addPolygon()'s points); another count throws.
    @param time the keyframe time in seconds (Pose::time).
    @return the pose's index. */
    int addPose(const std::string& name, InputArray vertices, double time = 0.0);
    /** @brief Replaces pose i. Its vertex count is not checked here (validate() checks it).
    @param i a pose index, 0 <= i < poseCount().
    @param pose the new pose; a name poseNameProblem() refuses throws a cv::Exception. */
    void setPose(int i, const Pose& pose);
    /** @brief Removes pose i.
    @param i a pose index, 0 <= i < poseCount(). */
    void removePose(int i);
    /** @brief Number of stored poses.
    @return the count. */
    int poseCount() const;
    /** @brief Pose i.
    @param i a pose index, 0 <= i < poseCount().
    @return a reference valid until the poses change. */
    const Pose& pose(int i) const;
    /** @brief Index of the first pose called name.
    @param name the name looked for.
    @return the index, or -1 when no pose has that name. */
    int findPose(const std::string& name) const;

    /** @brief The cage coordinates this multicage is meant to be bound with.

    Saved in the cage file as `coordinates: mean_value|harmonic|local_mean_value`.
    @return MEAN_VALUE, HARMONIC or LOCAL_MEAN_VALUE (a CoordinateType).
    @sa resolveCoordinates */
    int coordinates() const;
    /** @brief Sets the cage coordinates this multicage is meant to be bound with.
    @param coordinates MEAN_VALUE, HARMONIC or LOCAL_MEAN_VALUE; any other value throws a
    cv::Exception (StsOutOfRange). */
    void setCoordinates(int coordinates);

    /** @brief The frame of a clip the polygons and poses were drawn on (0: the first).

    Saved in the cage file as `clip_frame: N` (left out when 0). `multicage deform CLIP` tracks
    the cage forward and backward from that frame and carries the pose with it.
    @return the frame's index, >= 0. */
    int clipFrame() const;
    /** @brief Sets the frame of a clip the polygons and poses were drawn on.
    @param frame the frame's index, >= 0 (a negative one throws a cv::Exception, StsOutOfRange). */
    void setClipFrame(int frame);

    /** @brief The multicage with its polygons moved to a pose, for drawing a pose; poses are
    not copied.
    @param pose vertexCount() points, or +4 with the frame corners, which are ignored; another
    count throws a cv::Exception (StsBadSize).
    @return a multicage of the same image size whose polygons are the posed ones. */
    Multicage posed(InputArray pose) const;

    /** @brief The same multicage for an image of another size.

    Every coordinate c, of the polygons and of the poses, becomes
    `(c + 0.5) * newSize / imageSize - 0.5`, so the frame maps onto the new frame.
    @param newSize the new image size, not empty (nor may imageSize() be).
    @return the scaled copy. */
    Multicage scaled(Size newSize) const;

    /** @brief Writes image_size, coordinates, clip_frame (when not 0), polygons and poses (the
    cage file schema, docs/cli.md) into a cv::FileStorage; save() writes the same fields as
    standard YAML 1.2 or JSON.
    @param fs a FileStorage open for writing. */
    void write(FileStorage& fs) const;
    /** @brief Reads what write() writes, replacing this multicage.
    @param node the node write() wrote into.
    @throws cv::Exception for a malformed node, naming the field and the polygon or pose
    ("polygons[2]: odd number of coordinates (7)"). */
    void read(const FileNode& node);
    /** @brief Loads a YAML or JSON cage file (the extension picks the format).
    @param path a file ending in .yml, .yaml or .json.
    @return the multicage, which passes validateGeometry().
    @throws cv::Exception naming the file when the extension is not one of those, the file
    cannot be read, is not valid YAML/JSON, holds a malformed field (as read()), or describes
    a multicage validateGeometry() refuses. */
    static Multicage load(const String& path);
    /** @brief Saves to a YAML or JSON cage file, atomically: a reader never sees a partial file.
    @param path a file ending in .yml, .yaml or .json (the extension picks the format; another
    one throws a cv::Exception).
    @sa writeFileAtomic */
    void save(const String& path) const;

    /** @brief Draws the polygons, coloured by depth, onto image (for previews).
    @param image the picture to draw on, in place (BGR for the colours to read as meant); when
    its width is not imageSize().width, the polygons are scaled by its width over
    imageSize().width.
    @param thickness line thickness in pixels.
    @param drawVertices also draw a dot at every vertex. */
    void draw(InputOutputArray image, int thickness = 1, bool drawVertices = true) const;

  private:
    Size imageSize_;
    std::vector<std::vector<Point2f>> polygons_;
    std::vector<Pose> poses_;
    int coordinates_ = MEAN_VALUE;
    int clipFrame_ = 0;
};

/** @brief Writes an image through a temporary file in the same folder and a rename, so that
the path holds either the old file or the complete new one.
@param path the destination; its extension picks the format (cv::imencode).
@param image the image, as cv::imwrite takes it.
@param params encoder parameters, as cv::imwrite's.
@throws cv::Exception naming the file when there is no encoder for the extension, encoding
fails or the file cannot be written.
@sa convertForImageFormat */
CV_EXPORTS void imwriteAtomic(const String& path, InputArray image,
                              const std::vector<int>& params = std::vector<int>());
/** @brief Writes bytes to path atomically (temporary file, fsync, rename).
@param path the destination.
@param bytes the whole content.
@throws cv::Exception naming the file when it cannot be written. */
CV_EXPORTS void writeFileAtomic(const String& path, const std::string& bytes);

//! @} multicage_core

}  // namespace multicage
}  // namespace cv

#endif
