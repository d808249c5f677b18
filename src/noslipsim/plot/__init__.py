"""Figure helpers shared by every figure of the paper (and ``noslipsim plot``).

Figure scripts read datasets and draw with these; they never simulate.

- :func:`use_style`: the project's style file (:data:`STYLE`); one colour per law
  (:func:`law_color`), :data:`SERIES_COLORS` for curves that are not a law,
  :data:`REFERENCE_COLOR` for theory, :func:`equal_windows`, :func:`equal_panels` (equal boxes, aligned titles),
  :func:`frame_legend` (framed, off the data): module :mod:`noslipsim.plot.style`;
- :func:`draw_table`: a table, every element kind, periodic scenes as a patch
  of cells (:func:`scene_of` rebuilds a scene from a dataset's ``scene``
  attribute);
- :func:`draw_orbit`: an orbit's exact path, spin markers (:func:`draw_spin`),
  start and end dots (:func:`mark_ends`);
- :func:`draw_portrait`: a velocity portrait on the unit disk; :func:`draw_unvisited` hatches
  the part of the disk no orbit visited (:func:`unvisited_cells`);
- :func:`draw_stability_grid`: a 2D grid with a theoretical threshold;
- :func:`draw_angle`, :func:`draw_ray`, :func:`label_point`, :func:`ray_label_offset`,
  :func:`draw_force_arrow`: annotations of schematic figures;
- :func:`sphere_path`: the 3D path of a bouncing sphere; :func:`draw_arrow3d`: an arrow in 3D
  whose head stays on its shaft;
- :func:`draw_class_boundary`, :func:`draw_return_points`, :func:`draw_deviation`,
  :func:`draw_two_disk_setup`: stability figures (linear class over a survival
  map, returns to a wall, growth of a perturbation, the two-disk set-up);
- :func:`draw_layered_portrait`, :func:`draw_birkhoff`, :func:`draw_reduced_portrait`,
  :func:`orbit_colors`: phase portraits with one colour per orbit and the chaotic sea apart,
  the specular Birkhoff portrait, the reduced no-slip portrait in 3D;
- :func:`save_figure`: PDF and PNG, byte-stable; it refuses a panel without data;
- :func:`load_figure_data`, :func:`require_points`: a figure's dataset, refused when it holds
  nothing to draw (:class:`EmptyFigureError`); :func:`legend_problems`, :func:`check_legend`: the lines a
  legend hides and a spine it straddles;
- :func:`numbers_markdown`: the table of the paper's computed numbers.
- :mod:`noslipsim.plot.prose` (imported on its own): numbers quoted in prose, marked with their
  record of ``figures/numbers.json`` and checked against it.
"""
from .annotate import draw_angle, draw_force_arrow, draw_ray, label_point, ray_label_offset
from .checks import EmptyFigureError, check_legend, legend_problems, load_figure_data, require_points
from .flights import collision_frames, flight_samples, flight_states, fly, straight_flights
from .grids import draw_stability_grid
from .numbers import numbers_markdown
from .orbits import draw_orbit, draw_spin, mark_ends, orbit_nodes, orbit_path
from .phase import draw_birkhoff, draw_layered_portrait, draw_reduced_portrait, orbit_colors
from .portraits import draw_portrait, draw_unvisited, portrait_points, unvisited_cells
from .save import save_figure
from .sphere import draw_arrow3d, sphere_path
from .stability import draw_class_boundary, draw_deviation, draw_return_points, draw_two_disk_setup, return_points
from .style import (
           LAW_COLORS,
           REFERENCE_COLOR,
           SEA_COLOR,
           SERIES_COLORS,
           STYLE,
           equal_panels,
    equal_windows,
           frame_legend,
           law_color,
           style_context,
           use_style,
)
from .table import auto_window, check_window, draw_table, scene_of, table_shapes, view_window

__all__ = ["LAW_COLORS", "STYLE", "auto_window", "draw_orbit", "draw_portrait", "draw_spin", "draw_stability_grid",
           "draw_table", "law_color", "mark_ends", "numbers_markdown", "orbit_nodes", "orbit_path",
           "portrait_points", "save_figure", "scene_of", "style_context", "table_shapes", "use_style", "view_window"]
__all__ += ["check_window", "collision_frames", "flight_samples", "flight_states", "fly", "straight_flights"]
__all__ += ["draw_angle", "draw_arrow3d", "draw_force_arrow", "draw_ray", "label_point", "ray_label_offset",
            "sphere_path"]
__all__ += ["draw_class_boundary", "draw_deviation", "draw_return_points", "draw_two_disk_setup", "return_points"]
__all__ += ["draw_birkhoff", "draw_layered_portrait", "draw_reduced_portrait", "orbit_colors"]
__all__ += ["draw_unvisited", "unvisited_cells"]
__all__ += ["EmptyFigureError", "check_legend", "legend_problems", "load_figure_data", "require_points"]
__all__ += ["REFERENCE_COLOR", "SEA_COLOR", "SERIES_COLORS", "equal_panels", "equal_windows", "frame_legend"]
