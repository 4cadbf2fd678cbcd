#!/usr/bin/env python3
"""Checks a COCO file written by `sylva study` against the COCO detection schema with Python's
standard json only (pycocotools is not packaged in Debian 12): required keys and types, ids that
refer to existing images and categories, and every RLE mask decoded (uncompressed counts,
column-major, starting with zeros) against its annotation's area and bbox. Exit 0 when it holds."""
import json
import sys


def fail(message):
    print("check_coco: " + message, file=sys.stderr)
    sys.exit(1)


def decode_rle(segmentation):
    height, width = segmentation["size"]
    counts = segmentation["counts"]
    if sum(counts) != height * width:
        fail(f"RLE counts sum to {sum(counts)}, not {height} x {width}")
    mask = [[0] * width for _ in range(height)]
    position, value = 0, 0
    for run in counts:
        for k in range(position, position + run):
            mask[k % height][k // height] = value  # column-major
        position += run
        value = 1 - value
    return mask


def main(path):
    with open(path, encoding="utf-8") as f:
        coco = json.load(f)
    for key in ("info", "images", "annotations", "categories"):
        if key not in coco:
            fail(f"missing '{key}'")
    images = {}
    for image in coco["images"]:
        for key, kind in (("id", int), ("file_name", str), ("width", int), ("height", int)):
            if not isinstance(image.get(key), kind):
                fail(f"image {image.get('id')}: '{key}' must be {kind.__name__}")
        camera = image["camera"]
        if len(camera["intrinsics"]) != 9 or len(camera["world_from_camera"]) != 16:
            fail(f"image {image['id']}: camera intrinsics or pose malformed")
        images[image["id"]] = image
    categories = {c["id"]: c["name"] for c in coco["categories"]}
    if any(not isinstance(i, int) or not isinstance(n, str) for i, n in categories.items()):
        fail("categories need integer ids and string names")
    ids = set()
    for a in coco["annotations"]:
        if a["id"] in ids:
            fail(f"annotation id {a['id']} repeated")
        ids.add(a["id"])
        if a["image_id"] not in images:
            fail(f"annotation {a['id']}: no image {a['image_id']}")
        if a["category_id"] not in categories:
            fail(f"annotation {a['id']}: no category {a['category_id']}")
        if a["iscrowd"] not in (0, 1):
            fail(f"annotation {a['id']}: iscrowd must be 0 or 1")
        image = images[a["image_id"]]
        if a["segmentation"]["size"] != [image["height"], image["width"]]:
            fail(f"annotation {a['id']}: mask size differs from the image")
        mask = decode_rle(a["segmentation"])
        pixels = [(x, y) for y, row in enumerate(mask) for x, v in enumerate(row) if v]
        if len(pixels) != a["area"]:
            fail(f"annotation {a['id']}: area {a['area']} but the mask has {len(pixels)} pixels")
        xs = [p[0] for p in pixels]
        ys = [p[1] for p in pixels]
        box = [min(xs), min(ys), max(xs) - min(xs) + 1, max(ys) - min(ys) + 1]
        if a["bbox"] != box:
            fail(f"annotation {a['id']}: bbox {a['bbox']} but the mask spans {box}")
        ax, ay, aw, ah = a["amodal_bbox"]
        if not (ax <= box[0] and ay <= box[1] and ax + aw >= box[0] + box[2] and ay + ah >= box[1] + box[3]):
            fail(f"annotation {a['id']}: the amodal box {a['amodal_bbox']} does not hold the modal {box}")
        if not (ax >= 0 and ay >= 0 and ax + aw <= image["width"] and ay + ah <= image["height"]):
            fail(f"annotation {a['id']}: the amodal box {a['amodal_bbox']} leaves the image (it is clipped)")
        touches = ax == 0 or ay == 0 or ax + aw == image["width"] or ay + ah == image["height"]
        if a["truncated"] != (1 if touches else 0):
            fail(f"annotation {a['id']}: truncated {a['truncated']} but the amodal box touches the border: {touches}")
        if not 0 < a["visible_fraction"] <= 1:
            fail(f"annotation {a['id']}: visible_fraction {a['visible_fraction']}")
    print(f"check_coco: {len(images)} images, {len(coco['annotations'])} annotations, {len(categories)} categories")


if __name__ == "__main__":
    main(sys.argv[1])
