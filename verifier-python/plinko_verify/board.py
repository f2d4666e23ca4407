"""A board's geometry and its static shapes (docs/engine-spec.md, sections 4 and 6).

Every value is computed with the operations, in the order, the spec gives:
each step is an IEEE-754 double operation, as in the JavaScript engine."""

import math

from .versions import VERSIONS, SOLVER, MIN_ROWS, MAX_ROWS, RISKS, multipliers

PEG = 0
SEGMENT = 1
# px added to a peg's reach when cells list it (section 6.2).
NEAR_TOLERANCE = 1e-6


class Board:
    def __init__(self, version, rows, risk):
        if version not in VERSIONS:
            raise KeyError(version)
        if not (isinstance(rows, int) and MIN_ROWS <= rows <= MAX_ROWS):
            raise ValueError('rows must be an integer from %d to %d' % (MIN_ROWS, MAX_ROWS))
        if risk not in RISKS:
            raise ValueError('risk must be one of ' + ', '.join(RISKS))
        rules = VERSIONS[version]
        g = rules['geometry']
        self.version = version
        self.rows = rows
        self.risk = risk
        s = g['peg_spacing']
        row_spacing = g['row_spacing']
        ball_radius = g['ball_radius']
        peg_radius = g['peg_radius']
        last_row_pegs = rows + 2
        width = (last_row_pegs - 1) * s + 2 * g['side_margin']
        center_x = width / 2
        first_row_y = g['drop_height'] + 2 * ball_radius
        last_row_y = first_row_y + (rows - 1) * row_spacing
        bucket_line_y = last_row_y + g['bucket_depth']

        self.pegs = []
        for r in range(rows):
            count = r + 3
            y = first_row_y + r * row_spacing
            for k in range(count):
                self.pegs.append((center_x + (k - (count - 1) / 2) * s, y))

        run = s / 2
        slant_length = math.sqrt(run * run + row_spacing * row_spacing)
        shift = peg_radius * slant_length / row_spacing
        top_outer_x = s + shift
        bottom_outer_x = s + (rows - 1) * run + shift
        self.walls = []
        for side in (-1, 1):
            x_top = center_x + side * top_outer_x
            x_bottom = center_x + side * bottom_outer_x
            self.walls.append((x_top, 0.0, x_top, first_row_y))
            self.walls.append((x_top, first_row_y, x_bottom, last_row_y))
            self.walls.append((x_bottom, last_row_y, x_bottom, bucket_line_y + ball_radius))

        self.width = width
        self.peg_radius = peg_radius
        self.ball_radius = ball_radius
        self.drop_min_x = center_x - g['drop_zone_half_width']
        self.drop_max_x = center_x + g['drop_zone_half_width']
        self.drop_y = g['drop_height']
        self.bucket_line_y = bucket_line_y
        self.bucket_left_x = center_x - (last_row_pegs - 1) / 2 * s
        self.bucket_width = s
        self.multipliers = multipliers(version, rows, risk)
        self.ball = rules['ball']
        self.peg = rules['peg']
        self.release = rules['release']
        self.max_drop_ticks = rules['max_drop_ticks']
        self._build_shapes()
        self._build_grid()

    def bucket_at(self, x):
        bucket = math.floor((x - self.bucket_left_x) / self.bucket_width)
        return 0 if bucket < 0 else (self.rows if bucket > self.rows else bucket)

    def _build_shapes(self):
        """Static shapes by id: every peg (row by row, left to right), then the six walls."""
        shapes = []
        for (x, y) in self.pegs:
            shapes.append((PEG, x, y, self.peg_radius))
        for (x1, y1, x2, y2) in self.walls:
            ex = x2 - x1
            ey = y2 - y1
            length2 = ex * ex + ey * ey
            length = math.sqrt(length2)
            shapes.append((SEGMENT, x1, y1, x2, y2, -ey / length, ex / length, 1 / length2))
        self.shapes = shapes

    def _bounds(self, shape, margin):
        if shape[0] == PEG:
            _, a, b, c = shape
            return (a - c - margin, b - c - margin, a + c + margin, b + c + margin)
        _, a, b, c, d = shape[:5]
        return ((a if a < c else c) - margin, (b if b < d else d) - margin,
                (a if a > c else c) + margin, (b if b > d else d) + margin)

    def _near_box(self, shape, margin, min_x, min_y, max_x, max_y):
        if shape[0] == PEG:
            _, cx, cy, radius = shape
            dx = min_x - cx if cx < min_x else (cx - max_x if cx > max_x else 0.0)
            dy = min_y - cy if cy < min_y else (cy - max_y if cy > max_y else 0.0)
            reach = margin + radius + NEAR_TOLERANCE
            return dx * dx + dy * dy <= reach * reach
        half_w = (max_x - min_x) / 2
        half_h = (max_y - min_y) / 2
        reach = margin + math.sqrt(half_w * half_w + half_h * half_h)
        x = min_x + half_w
        y = min_y + half_h
        _, ax, ay, bx, by, _nx, _ny, inverse_length2 = shape
        ex = bx - ax
        ey = by - ay
        u = ((x - ax) * ex + (y - ay) * ey) * inverse_length2
        u = 0.0 if u < 0 else (1.0 if u > 1 else u)
        dx = x - (ax + ex * u)
        dy = y - (ay + ey * u)
        return dx * dx + dy * dy <= reach * reach

    def _build_grid(self):
        """The dense grid of section 6.2: per cell, the shapes a sub-step starting there may touch, by ascending id."""
        size = self.ball_radius * 1  # static cells per ball radius: 1
        inverse = 1 / size
        margin = self.ball_radius * (1 + SOLVER['max_travel_per_substep'])
        ranges = []
        for shape in self.shapes:
            b = self._bounds(shape, margin)
            ranges.append(tuple(math.floor(v * inverse) for v in b))
        min_x = min(r[0] for r in ranges)
        min_y = min(r[1] for r in ranges)
        max_x = max(r[2] for r in ranges)
        max_y = max(r[3] for r in ranges)
        columns = max_x - min_x + 1
        rows = max_y - min_y + 1
        cells = [[] for _ in range(columns * rows)]
        for shape_id, shape in enumerate(self.shapes):
            x0, y0, x1, y1 = ranges[shape_id]
            for iy in range(y0, y1 + 1):
                for ix in range(x0, x1 + 1):
                    if self._near_box(shape, margin, ix * size, iy * size, (ix + 1) * size, (iy + 1) * size):
                        cells[(iy - min_y) * columns + (ix - min_x)].append(shape_id)
        self.grid_inverse = inverse
        self.grid_min_x = min_x
        self.grid_min_y = min_y
        self.grid_columns = columns
        self.grid_rows = rows
        # Per cell, its shapes' records in ascending id: (PEG, id, cx, cy, r) or (SEGMENT, id, x1, y1, x2, y2, nx, ny, 1/length²).
        self.cells = [tuple((s[0], i) + s[1:] for i in ids for s in (self.shapes[i],)) for ids in cells]
