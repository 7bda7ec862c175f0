// The editor's document and its edits: a multicage (rest polygons and saved poses) plus the
// pose being edited. Everything here is GL-free and testable alone (tests/editor).
#ifndef MULTICAGE_EDITOR_DOCUMENT_HPP
#define MULTICAGE_EDITOR_DOCUMENT_HPP

#include <deque>
#include <opencv2/multicage.hpp>
#include <string>
#include <vector>

namespace multicage_editor {

/** Rest: the edits change the rest polygons (and rebind). Pose: they move the current pose.
Resize: no vertex edits; the frame's right and bottom edges set the size of a content-aware
resize of the rest multicage (resize_mode.hpp); positions() gives the rest there. */
enum class Mode { Rest, Pose, Resize };

/** What undo stores: small, copied whole. */
struct Document {
    cv::multicage::Multicage cage;  //!< rest polygons, saved poses, coordinate type
    /** The pose being edited: cage.vertexCount() points. A rest edit moves a vertex's pose
    position with it, so the pose keeps its displacement from rest. */
    std::vector<cv::Point2f> pose;
};

/** A new document for an image of this size (no polygon, empty pose). */
Document makeDocument(cv::Size imageSize);
/** A document for a loaded cage: the pose is the cage's first pose if it has one, else rest. */
Document makeDocument(const cv::multicage::Multicage& cage);

/** User vertex positions in vertices() order: rest or the current pose. */
std::vector<cv::Point2f> positions(const Document& doc, Mode mode);

/** Polygon and index within it of user vertex `id` (vertices() order); {-1,-1} if out of range. */
std::pair<int, int> locateVertex(const cv::multicage::Multicage& cage, int id);

/** Moves vertices (ids in vertices() order) by delta. Rest mode moves rest positions and the
pose positions with them (saved poses keep theirs); pose mode moves the current pose only. */
void moveVertices(Document& doc, Mode mode, const std::vector<int>& ids, cv::Point2f delta);
/** Adds a polygon (rest = pose = points); returns its index. */
int addPolygon(Document& doc, const std::vector<cv::Point2f>& points);
/** Removes polygon i (no-op when out of range). */
void removePolygon(Document& doc, int i);
/** Removes vertices (ids in vertices() order); a polygon left with fewer than 3 vertices is
removed. Saved poses of a polygon that lost vertices get its new rest positions. */
void removeVertices(Document& doc, const std::vector<int>& ids);
/** Inserts a vertex on edge (k, k+1) of polygon i at parameter t in [0,1] (rest and pose
interpolated alike); returns its id in vertices() order, or -1 when out of range. */
int insertVertex(Document& doc, int polygon, int edge, float t);
/** Applies the orientation rule when the rest geometry is valid, permuting the current pose
along; returns true when a polygon was reversed (vertex ids changed). */
bool orientDocument(Document& doc);
/** Stores the current pose as a named saved pose (replaces one of the same name). */
int addPose(Document& doc, const std::string& name);

/** Whether the rest multicage can be bound (validateGeometry); why gets the reason. */
bool restValid(const Document& doc, std::string* why);
/** Whether the current pose keeps the polygons simple and disjoint (a multicage made of the
pose positions passes validateGeometry); why gets the reason, prefixed with "pose: ". */
bool poseValid(const Document& doc, std::string* why);

/** Nearest vertex within radius (image pixels) of p, or -1. */
int hitVertex(const std::vector<cv::Point2f>& pts, cv::Point2f p, float radius);
/** Nearest edge within radius of p: polygon, edge index and parameter t; false if none. */
bool hitEdge(const cv::multicage::Multicage& cage, const std::vector<cv::Point2f>& pts,
             cv::Point2f p, float radius, int* polygon, int* edge, float* t);
/** Polygon whose interior (at the given positions) holds p, the deepest one; -1 if none. */
int hitPolygon(const cv::multicage::Multicage& cage, const std::vector<cv::Point2f>& pts,
               cv::Point2f p);

/** Undo/redo of whole documents: push() the state before each edit. */
class History {
  public:
    explicit History(size_t capacity = 200) : capacity_(capacity) {}
    /** Records `before` as the state to return to; clears the redo list. */
    void push(const Document& before);
    /** Replaces doc with the previous state (doc itself goes to redo); false if none. */
    bool undo(Document& doc);
    bool redo(Document& doc);
    size_t undoCount() const { return undo_.size(); }
    size_t redoCount() const { return redo_.size(); }
    void clear() {
        undo_.clear();
        redo_.clear();
    }

  private:
    size_t capacity_;
    std::deque<Document> undo_, redo_;
};

}  // namespace multicage_editor

#endif
