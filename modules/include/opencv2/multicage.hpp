/** @file
@brief The umbrella header of multicage: multicage image deformation on the GPU, for OpenCV
pipelines.

    Multicage  -> bind() -> Binding -> Deformer (GPU or CPU) -> cv::Mat
    proposeMulticage() makes a multicage from an image.

Includes every public header of the library; the groups below follow its modules.
@ingroup multicage
*/
#ifndef OPENCV2_MULTICAGE_HPP
#define OPENCV2_MULTICAGE_HPP

/**
@defgroup multicage Multicage image deformation

Multicage image deformation (Meng, Zhang, Dong, Paul 2011, "Multicage Image Deformation On
GPU"): disjoint nested polygons over an image, every pixel bound once to all their vertices,
then each pose of the vertices is an image deformed in milliseconds. An inner polygon protects
what it encloses: move the outer one and the inner region stays nearly rigid.

@{
    @defgroup multicage_core Multicage, poses and image files
    The multicage (polygons plus the image frame, paper §3.1), its poses and cage files, and
    image files read and written without silent damage (modules/core).

    @defgroup multicage_coords Cage coordinates and binding
    Mean value coordinates (Floater 2003; Hormann & Floater 2006), the paper's Algorithm 1
    over a multicage, harmonic coordinates (Joshi et al. 2007; DeRose & Meyer 2006) and local
    mean value coordinates: every node of a grid bound to every vertex (modules/coords).

    @defgroup multicage_pack Packing coefficients into textures
    The paper's packing of a binding into one RGBA texture (§4, Eq. 6-7, Fig. 6), with a
    texture-array fallback for layouts over the GPU's texture limit (modules/pack).

    @defgroup multicage_gpu GPU deformation and binding
    A headless EGL context, GLDeformer for callers that own an OpenGL context, and mean value
    binding in a compute shader (paper §4). The library's only EGL/OpenGL code (modules/gpu).

    @defgroup multicage_deform Deformer: images deformed to poses
    Binds an image once and deforms it to any number of poses on the GPU or the CPU, gives
    the inverse maps for cv::remap, and where points land (modules/deform).

    @defgroup multicage_propose Automatic multicage proposal
    A valid, oriented multicage proposed from an image (the paper's §6 future work), with
    inner polygons that protect faces and salient features (modules/propose).

    @defgroup multicage_animate Animation and augmentation
    Keyframed poses rendered to video, GIF or PNG frames, and random valid fold-free poses for
    data augmentation (modules/animate).

    @defgroup multicage_resize Content-aware resizing
    Resizing as one pose per target size (the paper's §6 future work): what the multicage
    protects keeps its shape, the background absorbs the change (modules/resize).

    @defgroup multicage_track Tracking a multicage through a clip
    CageTracker: each polygon follows what it encloses from frame to frame, and a cut or a lost
    polygon is reported so that the caller proposes again (modules/track).

    @defgroup multicage_reframe Reframing clips
    VideoReframer: a clip to another aspect ratio, each frame's tracked multicage resized, with
    windows and poses smoothed over time so that subjects glide (modules/reframe).
@}
*/

/** @namespace cv
@brief OpenCV's namespace; multicage adds cv::multicage to it.
*/

/** @namespace cv::multicage
@brief Multicage image deformation: the multicage, cage coordinates, packing, the GPU and CPU
Deformers, proposal, animation, augmentation, content-aware resizing, tracking and reframing
clips.
*/

#include <opencv2/multicage/animate.hpp>
#include <opencv2/multicage/augment.hpp>
#include <opencv2/multicage/coordinates.hpp>
#include <opencv2/multicage/deformer.hpp>
#include <opencv2/multicage/gpu.hpp>
#include <opencv2/multicage/imageio.hpp>
#include <opencv2/multicage/multicage.hpp>
#include <opencv2/multicage/packing.hpp>
#include <opencv2/multicage/propose.hpp>
#include <opencv2/multicage/reframe.hpp>
#include <opencv2/multicage/resize.hpp>
#include <opencv2/multicage/track.hpp>

#endif
