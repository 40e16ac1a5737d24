"""Lane shapes of a SUMO network file (net.net.xml), the map under the run report's trajectories.

SUMO network coordinates, after the network's netOffset, are the run's ENU coordinates unchanged
(simulator/scenario.hpp), so the shapes are drawn as they are.
"""

import xml.etree.ElementTree as ElementTree

from .errors import ReportInputError


def lane_polylines(path):
    """[[(x, y), ...], ...]: every lane's centre line (internal junction lanes included)."""
    lanes = []
    try:
        for _, element in ElementTree.iterparse(path, events=("end",)):
            if element.tag == "lane":
                shape = element.get("shape", "")
                points = []
                for pair in shape.split():
                    xyz = pair.split(",")
                    points.append((float(xyz[0]), float(xyz[1])))
                if len(points) >= 2:
                    lanes.append(points)
            elif element.tag == "edge":
                element.clear()
    except ElementTree.ParseError as e:
        raise ReportInputError(f"{path}:{e.position[0]}: not a SUMO network: {e}") from None
    except (ValueError, IndexError):
        raise ReportInputError(f"{path}: a lane shape that is not 'x,y x,y ...'") from None
    return lanes


def as_trace_xy(lanes):
    """The lanes as one x list and one y list with None between lanes (one Plotly trace)."""
    xs, ys = [], []
    for points in lanes:
        for x, y in points:
            xs.append(round(x, 2))
            ys.append(round(y, 2))
        xs.append(None)
        ys.append(None)
    return xs, ys
