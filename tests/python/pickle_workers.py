"""Functions that run in worker processes started with the 'spawn' method (test_pickle.py):
they must be importable by name, so they live in a module of their own."""

import numpy as np

import multicage as mc


def deform_in_worker(job):
    """Receives a Deformer, a Multicage, a Pose and a Binding through pickle, uses them, and
    sends them (and what they computed) back through pickle."""
    deformer, cage, pose, binding = job
    out = deformer.deform(pose.vertices)
    from_binding = mc.Deformer(deformer_image(deformer), binding, backend="cpu").deform(pose.vertices)
    return out, from_binding, cage, pose, binding, deformer


def deformer_image(deformer):
    # The image a Deformer pickles as: its rest-pose output on the CPU backend.
    return deformer.deform(deformer.binding.rest_vertices[:-4])


def fail_in_worker(cage):
    # A library error raised in a worker comes back to the parent as multicage.Error.
    return mc.Deformer(np.zeros((100, 100), np.uint8), cage, backend="cpu")
