#!/usr/bin/env python3
"""A PyTorch training loop's data pipeline with multicage augmentation: a Dataset of photos and
their masks, a torchvision Compose with multicage.TorchMulticageWarp, a DataLoader with worker
processes (fork or spawn), and a few steps of a tiny segmentation network.

    PYTHONPATH=build/python /usr/bin/python3 samples/python/train_loop.py [--workers 2]
        [--start-method spawn] [--steps 4] [--size 128] [--seed 0]

Reproducible in any worker: Dataset.__getitem__ seeds torch with (seed, index) before running
the Compose, so every random transform in it, MulticageWarp included, draws the same for a
sample whichever worker (or the main process) loads it. One multicage is proposed per photo on
first use and cached by name (per worker), and saved in --cage-dir when given.

Needs Debian's python3-torch and python3-torchvision.
"""

import argparse
import os
import sys

from sample_imports import cv2, np
from sample_imports import multicage as mc

try:
    import torch
    import torchvision
except ImportError as e:
    sys.exit(f"train_loop.py: {e}; install python3-torch and python3-torchvision (Debian)")

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data")


class PhotoMasks(torch.utils.data.Dataset):
    """Every photo of a folder, SIZE x SIZE, with its foreground mask
    (multicage.propose_segmentation), as {'image': 3xHxW uint8, 'mask': HxW uint8}; `length`
    samples cycle through the photos. The transform gets the sample as a dict of tensors."""

    def __init__(self, folder=DATA, size=128, length=16, transform=None, seed=0):
        names = sorted(n for n in os.listdir(folder) if n.lower().endswith((".jpg", ".png")))
        self.photos = []
        for n in names:
            image = cv2.resize(cv2.imread(os.path.join(folder, n)), (size, size), interpolation=cv2.INTER_AREA)
            mask = (mc.propose_segmentation(image) > 0).astype(np.uint8)
            self.photos.append((n, image, mask))
        self.length, self.transform, self.seed = length, transform, seed

    def __len__(self):
        return self.length

    def __getitem__(self, index):
        name, image, mask = self.photos[index % len(self.photos)]
        sample = {"image": torch.from_numpy(np.ascontiguousarray(image.transpose(2, 0, 1))),
                  "mask": torch.from_numpy(mask), "name": name}
        # One seed per (run, sample): the same augmentation in every worker.
        torch.manual_seed(mc.sample_seed(self.seed, index))
        return self.transform(sample) if self.transform is not None else sample


class ImageOnly:
    """Applies a tensor transform (torchvision's) to sample['image'] only."""

    def __init__(self, transform):
        self.transform = transform

    def __call__(self, sample):
        return dict(sample, image=self.transform(sample["image"]))


def make_pipeline(size=128, length=16, seed=0, amplitude=None, cage_dir=None):
    """The Dataset with its Compose: multicage warp (image bilinear, mask nearest), then the
    image to float and normalised, as a training loop wants it."""
    warp = mc.MulticageWarp(amplitude=amplitude if amplitude is not None else size / 16, grid_step=4,
                            cage_dir=cage_dir, protect=False)
    transform = torchvision.transforms.Compose([
        mc.TorchMulticageWarp(warp),
        ImageOnly(torchvision.transforms.ConvertImageDtype(torch.float32)),
        ImageOnly(torchvision.transforms.Normalize([0.5] * 3, [0.25] * 3)),
    ])
    return PhotoMasks(size=size, length=length, transform=transform, seed=seed)


def collate(samples):
    return {"image": torch.stack([s["image"] for s in samples]),
            "mask": torch.stack([s["mask"] for s in samples]),
            "name": [s["name"] for s in samples]}


def loader(dataset, workers=2, start_method="spawn", batch_size=4):
    kwargs = {"num_workers": workers, "batch_size": batch_size, "shuffle": False, "collate_fn": collate}
    if workers > 0:
        kwargs["multiprocessing_context"] = start_method
    return torch.utils.data.DataLoader(dataset, **kwargs)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--start-method", default="spawn", choices=["fork", "spawn", "forkserver"])
    p.add_argument("--steps", type=int, default=4, help="batches to train on (default: %(default)s)")
    p.add_argument("--size", type=int, default=128)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--cage-dir", default=None, help="save the proposed cages here (and read them back)")
    p.add_argument("--save", default=None, help="write the first batch's images and masks to this PNG")
    args = p.parse_args(argv)
    torch.manual_seed(args.seed)
    dataset = make_pipeline(args.size, length=4 * args.steps, seed=args.seed, cage_dir=args.cage_dir)
    net = torch.nn.Sequential(torch.nn.Conv2d(3, 8, 3, padding=1), torch.nn.ReLU(),
                              torch.nn.Conv2d(8, 1, 3, padding=1))
    optimiser = torch.optim.SGD(net.parameters(), lr=0.05)
    for step, batch in enumerate(loader(dataset, args.workers, args.start_method)):
        logits = net(batch["image"])[:, 0]
        loss = torch.nn.functional.binary_cross_entropy_with_logits(logits, batch["mask"].float())
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
        print(f"step {step}: {len(batch['name'])} samples ({', '.join(batch['name'])}), loss {loss.item():.4f}")
        if step == 0 and args.save:
            images = (batch["image"] * 0.25 + 0.5).clamp(0, 1).mul(255).byte().permute(0, 2, 3, 1).numpy()
            masks = batch["mask"].numpy() * 255
            rows = [np.hstack([im, cv2.cvtColor(m, cv2.COLOR_GRAY2BGR)]) for im, m in zip(images, masks)]
            cv2.imwrite(args.save, np.vstack(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
