/** @file
@brief Automatic multicage proposal from an image (the paper's §6 future work).

    segment -> clean -> nested contours -> dilate by a margin -> simplify to a vertex budget
    (keeping every polygon simple and all polygons disjoint) -> orient by depth -> validate

@ingroup multicage_propose
*/
#ifndef OPENCV2_MULTICAGE_PROPOSE_HPP
#define OPENCV2_MULTICAGE_PROPOSE_HPP

#include <opencv2/multicage/multicage.hpp>

namespace cv {
namespace multicage {

//! @addtogroup multicage_propose
//! @{

/** @brief How proposeMulticage() decides which pixels belong to an object
(ProposeParams::method).
@sa proposeMethodName, docs/propose/README.md
*/
enum ProposeMethod {
    /** The subject model's map fused with the faces and GrabCut where a model runs
    (ProposeParams::segmenter); else PROPOSE_THRESHOLD when the image border is mostly one
    colour (an object on a plain background), and PROPOSE_GRABCUT from the image frame inward
    otherwise (see docs/propose/README.md). */
    PROPOSE_AUTO = 0,
    /** Otsu threshold on the distance from the background colour (the median colour of the
    image border): objects on a plain background. */
    PROPOSE_THRESHOLD = 1,
    /** Adaptive (local mean) threshold of the same distance: uneven lighting. */
    PROPOSE_ADAPTIVE = 2,
    /** GrabCut from ProposeParams::rect, or from the image frame inward when rect is empty
    (a strip along the frame is background, reopened where the subject goes on past the
    frame), kept where it holds what GrabCut from a rectangle around the salient part finds.
    Runs on a copy downscaled to ProposeParams::grabCutMaxSide. */
    PROPOSE_GRABCUT = 3,
    /** opencv_contrib StaticSaliencyFineGrained, thresholded by Otsu. */
    PROPOSE_SALIENCY = 4,
    /** opencv_contrib StaticSaliencySpectralResidual (Hou & Zhang 2007): coarser, fastest. */
    PROPOSE_SPECTRAL_RESIDUAL = 5,
    /** The image is a user mask: one channel, non-zero pixels are objects. */
    PROPOSE_MASK = 6,
    /** The image is a label image (CV_8U, CV_16U or CV_32S, one channel): 0 is background,
    every other label a class of its own. Touching labels are split along the line halfway
    between them, so each label component gets its own polygon. */
    PROPOSE_LABELS = 7
};

/** @brief What protectFeatures() protects inside a polygon (ProposeParams::protect).
@sa protectDetectorName, docs/faces/README.md
*/
enum ProtectDetector {
    /** Salient blobs (ProposeParams::method inside the polygon; PROPOSE_AUTO: fine-grained
    saliency), and for a photo the regions that differ in colour from what is around them,
    compact and alone of their kind (a badge, a name tag, a patch; docs/propose); each kept
    where it holds more edge detail than the polygon and its surroundings. */
    PROTECT_SALIENCY = 0,
    /** Faces: frontal and profile (both directions) faces found by cv::CascadeClassifier with
    OpenCV's Haar cascades (Debian package opencv-data), optionally confirmed by an eye inside
    (ProposeParams::faceEyes). Each face becomes a rounded box hugging it (a superellipse a
    small margin around the detected box grown to the forehead and the chin), nested in the
    polygon around it and crossing no other; faces whose polygons would overlap merge.
    proposeProtectedMulticage() keeps the outline clear of the face's polygon by the band the
    polygon needs, the outline otherwise following the head, and binds with local mean value
    coordinates, so that moving the outline leaves the face a similarity.
    No cascade file: cv::Exception (StsObjectNotFound) naming the package. No face found:
    nothing added. */
    PROTECT_FACES = 1,
    /** Faces first (they get the budget first), then what PROTECT_SALIENCY finds, kept away
    from the faces' polygons (a quarter of a face size; a face size for Coordinates
    MEAN_VALUE) and off the garment's opening under each face (a shirt front, a tie). No
    cascade installed: PROTECT_SALIENCY's regions only, no error (faceCascadeFile() tells). */
    PROTECT_ALL = 2
};

/** @brief Where proposeMulticage() learns what the subject of a photo is
(ProposeParams::segmenter).

Masks and label images (PROPOSE_MASK, PROPOSE_LABELS) are the caller's word and use none.
@sa segmenterModelFile, subjectMap, docs/models.md
*/
enum ProposeSegmenter {
    /** SEGMENTER_MODEL when a subject model is found (segmenterModelFile()), else
    SEGMENTER_CLASSIC. */
    SEGMENTER_AUTO = 0,
    /** A learned salient-object network (U^2-Net-P by default, docs/models.md) run through
    OpenCV's dnn module gives a subject map; the proposal fuses it with the faces and the
    frame-inward GrabCut (docs/propose/README.md). No model found: cv::Exception. */
    SEGMENTER_MODEL = 1,
    /** Hand-written cues only: GrabCut seeded by the person prior or from the frame inward,
    and the plain-background threshold. */
    SEGMENTER_CLASSIC = 2
};

/** @brief Environment variable naming a subject model file, looked at after
ProposeParams::segmenterModel (docs/models.md). */
#define MULTICAGE_SEGMENTER_ENV "MULTICAGE_SEGMENTER_MODEL"
/** @brief Environment variable naming the folder that holds the installed data (its models/
subfolder): where set, it replaces the build tree's and the install prefix's share/multicage,
for a prefix moved after installing. */
#define MULTICAGE_DATA_ENV "MULTICAGE_DATA_DIR"

/** @brief Folder of OpenCV's Haar cascades on Debian (package opencv-data). */
#define MULTICAGE_DEBIAN_CASCADE_DIR "/usr/share/opencv4/haarcascades"

/** @brief Parameters of proposeMulticage() and protectFeatures().

Every field has a default that works on photographs; lengths are in pixels of the input
image. */
struct CV_EXPORTS ProposeParams {
    int method = PROPOSE_AUTO;    //!< ProposeMethod
    int maxVertices = 80;         //!< budget over all polygons (user vertices, frame excluded)
    int maxPolygonVertices = 32;  //!< budget of one polygon (at least 4)
    int maxPolygons = 12;         //!< the largest regions win when there are more
    int maxDepth = 3;             //!< deepest nesting kept (1: top-level polygons only)
    /** Distance from the object to its polygon. A polygon simplified within `margin` still
    encloses every object pixel; < 0 picks 1.2% of the image diagonal (at least 3 px). */
    float margin = -1.f;
    /** Regions (and holes) smaller than this fraction of the image area are dropped. */
    double minRegionArea = 0.004;
    /** Radius of the morphological open/close that removes specks and bridges pin holes;
    < 0 picks 0.5% of the longer image side (at least 1 px), 0 switches it off. */
    int morphologyRadius = -1;
    /** The proposal runs on a copy whose longer side is at most this (0: full size); the
    polygons are scaled back. Segmentation does not need more, and time falls with area. */
    int workingSize = 512;
    Rect rect;  //!< GrabCut's initial rectangle (empty: found automatically)
    /** GrabCut's iterations. 2, because on the benchmark photos the mask after 2 is the mask
    after 4, in less time (docs/propose/history.md, "Speed"). Where GrabCut finds the subject
    from the image frame inward (no face, no rect), it goes on past them, up to 5, until an
    iteration moves at most 1% of the pixels: a subject still being carved out of its start
    (docs/propose/README.md, "The frame-inward GrabCut"). */
    int grabCutIterations = 2;
    int grabCutMaxSide = 240;  //!< GrabCut's own working size (its cost is per pixel)
    /** ProtectDetector: what protectFeatures() protects. The default, PROTECT_ALL, is the
    one default of the library, `multicage propose`, Python's propose_multicage and the
    editor's Propose: faces first, then the textured salient features (see PROTECT_ALL). */
    int protect = PROTECT_ALL;
    /** Folder holding haarcascade_frontalface_alt2.xml, haarcascade_profileface.xml and
    haarcascade_eye.xml (only there when given); empty: MULTICAGE_DEBIAN_CASCADE_DIR, then
    /usr/share/opencv/haarcascades. */
    String cascadeDir;
    /** Keep only the faces in which haarcascade_eye.xml finds an eye (fewer false faces,
    misses faces with closed or hidden eyes). */
    bool faceEyes = false;
    /** In a cage bound with mean value coordinates (Multicage::coordinates()), a face's
    polygon also holds four small fixed polygons (anchors, 16 vertices) spread over the face:
    they cut what leaks into the face from a moved outline (docs/faces/README.md measures by
    how much). Off, and in a cage with local mean value or harmonic coordinates (the protected
    proposal's), where they change nothing, the face's polygon holds its eyes instead where a
    face is at least 60 px wide and the eye cascades find both. */
    bool faceAnchors = true;
    /** Faces are searched on a copy whose longer side is at most this (0: full size): the
    cascades' cost grows with area. The smallest face found there is 24 pixels of the copy,
    7.5% of the longer side at 320; the frontal cascade also searches a copy twice as large for
    the smaller faces only, down to 3.75% (a full figure's, a group's). */
    int faceWorkingSize = 320;
    /** ProposeSegmenter: where the subject cue comes from (SEGMENTER_AUTO: the learned model
    when one is found, else the classic cues). */
    int segmenter = SEGMENTER_AUTO;
    /** A subject model (ONNX) to use instead of the default: one RGB image in (1x3xHxW, the
    size its graph declares, 320x320 where it declares none; 0-1, ImageNet mean and deviation),
    one subject map out (1x1xHxW, 0-1). The default runs at 256x256. Empty: the
    environment variable MULTICAGE_SEGMENTER_ENV, then the pinned model in the build tree,
    then in the install prefix (or in MULTICAGE_DATA_ENV's folder; segmenterModelFile()). */
    String segmenterModel;
};

/** @brief Proposes a valid, oriented multicage that encloses the objects of an image.

The result's polygons enclose the segmented regions at distance `margin`, one polygon per
region, nested as the regions are (an object inside another object's hole gets depth 2),
oriented (orient()), and always pass validate(): vertices strictly inside the frame, every
polygon simple, all polygons pairwise disjoint. Where simplification would make polygons
cross, the tolerance grows, then the convex hull is tried, then the smaller (or inner)
polygon is dropped.
@param image 8-bit (or 16-bit / float, rescaled) 1, 3 or 4 channels; for PROPOSE_MASK a
one-channel mask; for PROPOSE_LABELS a one-channel label image.
@param params method, vertex budgets, margin, minimum region area, maximum depth, ...
@return a Multicage of the image's size; one with no polygon when no region is larger than
minRegionArea.
@throws cv::Exception (StsBadArg) for an empty image or a constant one (nothing to segment)
and for parameters out of range.
@sa proposeProtectedMulticage, proposeSegmentation, docs/propose/README.md
*/
CV_EXPORTS Multicage proposeMulticage(InputArray image,
                                      const ProposeParams& params = ProposeParams());

/** @brief The multicage the tools propose by default (`multicage propose`, the editor, the
demo).

proposeMulticage(), then protectFeatures() inside every top-level polygon, so the result is
an outline around each object plus inner polygons protecting its salient features. With
PROPOSE_MASK or PROPOSE_LABELS the input is a mask, not a photo: nothing is added. The inner
polygons share params' budgets (maxVertices, maxPolygons) with the outlines.
@param image as proposeMulticage().
@param params as proposeMulticage(); protect picks what the inner polygons protect.
@return the valid, oriented multicage.
@throws cv::Exception as proposeMulticage().
*/
CV_EXPORTS Multicage proposeProtectedMulticage(InputArray image,
                                               const ProposeParams& params = ProposeParams());

/** @brief The segmentation that proposeMulticage() encloses, after cleaning.
@param image as proposeMulticage(); not empty (else cv::Exception, StsBadArg).
@param[out] mask CV_8UC1 of the image's size, 255 on the region pixels the polygons must
contain (the same regions, before the budget keeps the largest). For PROPOSE_LABELS it holds
the label components.
@param params as proposeMulticage().
*/
CV_EXPORTS void proposeSegmentation(InputArray image, OutputArray mask,
                                    const ProposeParams& params = ProposeParams());

/** @brief Automatic feature preservation: proposes protective inner polygons around the
salient features inside polygon `polygon` of `cage`, so that moving that polygon leaves them
almost rigid (paper §3.1: an inner polygon protects what it encloses).

Features are kept inside the polygon at least `margin` from its edges and from the polygons
already nested in it. No feature found or no budget left: the cage is returned unchanged.
@param image the image the cage was drawn on (its size must match cage.imageSize(), else
StsBadSize).
@param cage a multicage that passes validateGeometry() (else StsBadArg).
@param polygon index of the polygon the user will move (out of range: StsOutOfRange).
@param params segmentation method (PROPOSE_AUTO: saliency within the polygon), margin,
budgets; maxVertices is the budget of the whole result, existing vertices included.
@return a copy of cage with the new polygons appended (existing polygons and poses unchanged,
poses extended with the new vertices at rest), oriented and valid.
@throws cv::Exception as said above, and for an empty image (StsBadArg).
*/
CV_EXPORTS Multicage protectFeatures(InputArray image, const Multicage& cage, int polygon,
                                     const ProposeParams& params = ProposeParams());

/** @brief Faces in an image, as protectFeatures() with PROTECT_FACES finds them.

Frontal and profile (both directions) detections on a copy at most params.faceWorkingSize
wide or high, histogram-equalised, and frontal detections of the faces too small for that copy
on one twice as large (enlarged where the image is smaller); in a colour image only boxes whose
middle is mostly skin-coloured (Haar cascades also fire on crowds and clothing), in an image without
colour only frontal boxes on which 5 search windows agree or in which an eye is found (patterns such
as a coin's portrait fire the cascade too); optionally confirmed by an eye (params.faceEyes);
a box that holds a smaller one, on which as many search windows agree, gives way to it;
detections of one face (sharing at least a quarter of the smaller box) merged into their
bounding box, so the boxes of two faces may overlap a little.
@param image the photo.
@param params faceWorkingSize, faceEyes and cascadeDir are read.
@return rectangles in input pixels, largest first.
@throws cv::Exception (StsObjectNotFound) when the frontal cascade is not installed:
"... install the Debian package opencv-data, or set ProposeParams::cascadeDir".
*/
CV_EXPORTS std::vector<Rect> detectFaces(InputArray image,
                                         const ProposeParams& params = ProposeParams());

/** @brief Path of the frontal face cascade protectFeatures() would use.
@param params cascadeDir is read; empty: the Debian folders.
@return the path, or an empty string when none is installed.
*/
CV_EXPORTS String faceCascadeFile(const ProposeParams& params = ProposeParams());

/** @brief proposeProtectedMulticage() that also returns the faces it found.

With faces, the outlines are made to enclose every face with room for its protective
polygon, and each face gets an inner polygon in the outline around it.
@param image as proposeMulticage().
@param params as proposeProtectedMulticage().
@param[out] faces when not null, receives the faces found (with PROTECT_FACES or PROTECT_ALL;
empty otherwise), in input pixels.
@return the valid, oriented multicage.
*/
CV_EXPORTS Multicage proposeProtectedMulticage(InputArray image, const ProposeParams& params,
                                               std::vector<Rect>* faces);

/** @brief The subject model proposeMulticage() would run for `params`.

@param params     segmenter and segmenterModel are read (SEGMENTER_CLASSIC: none)
@param why        when not null, receives how the model was found ("ProposeParams::segmenterModel",
                  "MULTICAGE_SEGMENTER_MODEL", "the build tree", "the install prefix") or why
                  there is none, with how to get one
@return the model's path, or an empty string when none is found. A path given explicitly (the
field or the environment variable) is returned as given, whether or not it exists: reading it
then fails with a cv::Exception naming it. */
CV_EXPORTS String segmenterModelFile(const ProposeParams& params = ProposeParams(),
                                     String* why = nullptr);

/** @brief The learned subject map of an image: what the subject model sees as the subject.

The model is read once per process and shared by every thread (its runs take turns).
@param image   8-bit (or 16-bit / float, rescaled) 1, 3 or 4 channels
@param map     CV_32FC1 of the image's size, 0 (background) to 1 (subject)
@param params  segmenterModel and the look-up of segmenterModelFile()
@throws cv::Exception (StsObjectNotFound) when no model is found, and (StsParseError) naming
the file when it is not a subject model: a truncated, corrupt or foreign file, or a default
model whose size or sha256 is not the pinned one (docs/models.md). */
CV_EXPORTS void subjectMap(InputArray image, OutputArray map,
                           const ProposeParams& params = ProposeParams());

/** @brief Name of a ProposeSegmenter.
@param segmenter a ProposeSegmenter.
@return "auto", "model" or "classic"; "unknown" for any other value.
@sa parseSegmenter */
CV_EXPORTS const char* segmenterName(int segmenter);
/** @brief The ProposeSegmenter called name.
@param name "auto", "model" or "classic".
@return the ProposeSegmenter, or -1 for an unknown name. */
CV_EXPORTS int parseSegmenter(const String& name);

/** @brief Name of a ProtectDetector.
@param detector a ProtectDetector.
@return "saliency", "faces" or "all"; "unknown" for any other value.
@sa parseProtectDetector */
CV_EXPORTS const char* protectDetectorName(int detector);
/** @brief The ProtectDetector called name.
@param name "saliency", "faces" or "all".
@return the ProtectDetector, or -1 for an unknown name. */
CV_EXPORTS int parseProtectDetector(const String& name);

/** @brief Name of a ProposeMethod.
@param method a ProposeMethod.
@return "auto", "threshold", "adaptive", "grabcut", "saliency", "spectral", "mask" or
"labels"; "unknown" for any other value.
@sa parseProposeMethod */
CV_EXPORTS const char* proposeMethodName(int method);
/** @brief The ProposeMethod called name.
@param name one of the names proposeMethodName() gives.
@return the ProposeMethod, or -1 for an unknown name. */
CV_EXPORTS int parseProposeMethod(const String& name);

//! @} multicage_propose

}  // namespace multicage
}  // namespace cv

#endif
