"""A sphinx-gallery image scraper for GIFs: an example that writes a GIF in its folder shows it on its page."""
import glob
import os
import shutil


def gif_scraper(block, block_vars, gallery_conf):
    """Put the GIFs an example wrote (in its folder) into the gallery, after its matplotlib figures."""
    from sphinx_gallery.scrapers import figure_rst

    folder = os.path.dirname(block_vars["src_file"])
    names = []
    for gif in sorted(glob.glob(os.path.join(folder, "*.gif"))):
        target = next(block_vars["image_path_iterator"]).replace(".png", ".gif")
        shutil.move(gif, target)
        names.append(target)
    return figure_rst(names, gallery_conf["src_dir"])
