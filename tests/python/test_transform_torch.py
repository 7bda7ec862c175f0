"""Issue 23, item 5: TorchMulticageWarp in a torchvision Compose on CHW tensors, and the sample
training-loop pipeline (samples/python/train_loop.py) with 2 DataLoader workers, fork and
spawn, giving the batches one process gives."""

import sys

import numpy as np
import pytest

import multicage as mc
from conftest import SAMPLES

torch = pytest.importorskip("torch")
torchvision = pytest.importorskip("torchvision")

sys.path.insert(0, str(SAMPLES / "python"))
import train_loop  # noqa: E402


def test_tensor_in_compose_matches_the_numpy_transform(butterfly):
    """On a CHW tensor the adapter gives the numpy transform's pixels for the seed it drew
    from torch's generator, as a tensor of the same dtype; float tensors stay float."""
    warp = mc.MulticageWarp(amplitude=10, grid_step=4, cage=mc.Multicage.load(str(SAMPLES / "butterfly.yml")))
    adapter = mc.TorchMulticageWarp(warp)
    chw = torch.from_numpy(np.ascontiguousarray(butterfly.transpose(2, 0, 1)))
    compose = torchvision.transforms.Compose([adapter])
    torch.manual_seed(3)
    out = compose(chw)
    torch.manual_seed(3)
    seed = int(torch.randint(0, 2**62, (1,)).item())
    expected = warp(image=butterfly, seed=seed)["image"]
    assert out.dtype == torch.uint8 and tuple(out.shape) == tuple(chw.shape)
    np.testing.assert_array_equal(out.permute(1, 2, 0).numpy(), expected)
    assert not np.array_equal(expected, butterfly)
    f = compose(chw.float() / 255)
    assert f.dtype == torch.float32 and tuple(f.shape) == tuple(chw.shape)
    sample = adapter({"image": chw, "mask": torch.ones(butterfly.shape[:2], dtype=torch.uint8), "tag": 5})
    assert set(sample) == {"image", "mask", "tag"} and sample["tag"] == 5
    with pytest.raises(ValueError, match="CHW"):
        adapter(torch.zeros(4, 5))


def batches(dataset, workers, method):
    return [(b["image"].clone(), b["mask"].clone(), b["name"])
            for b in train_loop.loader(dataset, workers, method, batch_size=3)]


@pytest.mark.parametrize("method", ["fork", "spawn"])
def test_pipeline_with_two_workers_equals_one_process(method):
    dataset = train_loop.make_pipeline(size=64, length=7, seed=4)
    local = batches(dataset, 0, method)
    remote = batches(dataset, 2, method)
    assert len(local) == len(remote) == 3
    for (li, lm, ln), (ri, rm, rn) in zip(local, remote):
        assert ln == rn
        assert li.dtype == torch.float32 and tuple(li.shape[1:]) == (3, 64, 64)
        assert torch.equal(li, ri) and torch.equal(lm, rm)
    # The augmentation is there: the same photo (index 0 and its next cycle) comes out warped
    # differently, and a run with another seed differs.
    photos = len(dataset.photos)
    first, again = dataset[0]["image"], dataset[photos]["image"]
    assert not torch.equal(first, again)
    assert not torch.equal(local[0][0], batches(train_loop.make_pipeline(size=64, length=7, seed=5), 0, method)[0][0])
