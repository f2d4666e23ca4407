"""One drop from its seed to landing (docs/engine-spec.md, sections 5 to 8).

Written as one function over local variables: Python floats are IEEE-754
doubles and every operation below is the spec's, in its order, so the
bits match the JavaScript engine's."""

import math

from .board import PEG
from .random_stream import Arc4Random
from .state_hash import body_state_hash
from .versions import SOLVER

TWO_PI = 6.283185307179586
PI = 3.141592653589793
# px: widens the slab test of a wall so that rounding never rejects a wall that is touched (section 6.3).
SLAB_TOLERANCE = 1e-6


def initial_conditions(board, drop_seed):
    """x, y, vx, vy, angle, angular velocity of the ball at release (section 5)."""
    if not isinstance(drop_seed, str) or drop_seed == '':
        raise ValueError('dropSeed must be a non-empty string')
    rng = Arc4Random(drop_seed)
    release = board.release
    x = board.drop_min_x + (board.drop_max_x - board.drop_min_x) * rng.next()
    vx = (rng.next() * 2 - 1) * release['max_vx']
    vy = rng.next() * release['max_vy']
    angle = rng.next() * TWO_PI
    spin = (rng.next() * 2 - 1) * release['max_spin']
    return x, board.drop_y, vx, vy, angle, spin


def simulate_drop(board, drop_seed, on_tick=None, max_ticks=None):
    """Returns {'bucket', 'multiplier', 'ticks', 'stateHash'}; on_tick(tick, state) is called after every tick.

    max_ticks: a tick cap instead of the version's (section 8), to check the cap rule on drops that reach it."""
    x, y, vx, vy, angle, w = initial_conditions(board, drop_seed)
    radius = board.ball_radius
    ball = board.ball
    peg = board.peg
    mass = ball['density'] * PI * radius * radius
    inv_mass = 1 / mass
    inv_inertia = 2 / (mass * radius * radius)
    restitution = ball['restitution'] if ball['restitution'] > peg['restitution'] else peg['restitution']
    friction = math.sqrt(ball['friction'] * peg['friction'])
    kt = inv_mass + radius * radius * inv_inertia
    threshold = SOLVER['restitution_threshold']
    slop = SOLVER['linear_slop']
    fraction = SOLVER['correction_fraction']
    dt = SOLVER['timestep']
    gx = 0.0
    gy = SOLVER['gravity']
    abs_gx = gx
    abs_gy = gy
    max_substeps = SOLVER['max_substeps']
    max_impacts = SOLVER['max_impacts_per_substep']
    max_travel = radius * SOLVER['max_travel_per_substep']
    max_travel2 = max_travel * max_travel
    slab = radius + SLAB_TOLERANCE
    cells = board.cells
    inv_cell = board.grid_inverse
    grid_min_x = board.grid_min_x
    grid_min_y = board.grid_min_y
    columns = board.grid_columns
    grid_rows = board.grid_rows
    line_y = board.bucket_line_y
    max_ticks = board.max_drop_ticks if max_ticks is None else max_ticks
    sqrt = math.sqrt
    floor = math.floor
    no_candidates = ()

    tick = 0
    while True:
        # ---- one tick (section 7) ----
        speed_x = (-vx if vx < 0 else vx) + abs_gx * dt
        speed_y = (-vy if vy < 0 else vy) + abs_gy * dt
        travel2 = (speed_x * speed_x + speed_y * speed_y) * dt * dt
        substeps = 1
        while substeps < max_substeps and travel2 > substeps * substeps * max_travel2:
            substeps += 1
        h = dt / substeps
        for _ in range(substeps):
            vx += gx * h
            vy += gy * h
            angle += w * h
            if angle >= TWO_PI or angle < 0:
                angle -= floor(angle / TWO_PI) * TWO_PI
            remaining = 1.0
            impact = 0
            while impact < max_impacts and remaining > 0:
                impact += 1
                column = x * inv_cell - grid_min_x
                row = y * inv_cell - grid_min_y
                if column >= 0 and row >= 0 and column < columns and row < grid_rows:
                    candidates = cells[int(row) * columns + int(column)]
                else:
                    candidates = no_candidates
                dx = vx * h * remaining
                dy = vy * h * remaining
                first = -1
                first_time = 2.0
                cnx = cny = cdepth = 0.0
                if candidates:
                    a = dx * dx + dy * dy
                    for shape in candidates:
                        if shape[0] == PEG:
                            _, shape_id, px, py, pr = shape
                            mx = x - px
                            my = y - py
                            b = mx * dx + my * dy
                            reach = radius + pr
                            reach2 = reach * reach
                            c = mx * mx + my * my - reach2
                            # the peg prefilter (section 6.3)
                            if b >= 0 or (c > 0 and a + 2 * b + c > 0 and (-b >= a or b * b < a * c)):
                                continue
                            if c > 0:
                                discriminant = b * b - a * c
                                if discriminant < 0:
                                    continue
                                t = c / (-b + sqrt(discriminant))
                                if t > 1 or not (t < first_time):
                                    continue
                                first = shape_id
                                first_time = t
                                cnx = (mx + dx * t) / reach
                                cny = (my + dy * t) / reach
                                cdepth = 0.0
                            elif first_time > 0:
                                dist2 = c + reach2
                                first = shape_id
                                first_time = 0.0
                                if dist2 > 0:
                                    dist = sqrt(dist2)
                                    cnx = mx / dist
                                    cny = my / dist
                                    cdepth = reach - dist
                                else:
                                    cnx = 0.0
                                    cny = -1.0
                                    cdepth = reach
                            continue
                        # a wall (section 6.4)
                        _, shape_id, ax, ay, bx, by, snx, sny, inv_len2 = shape
                        side_start = (x - ax) * snx + (y - ay) * sny
                        side_end = side_start + dx * snx + dy * sny
                        if (side_start > slab and side_end > slab) or (side_start < -slab and side_end < -slab):
                            continue
                        hit = _sweep_segment(x, y, radius, dx, dy, ax, ay, bx, by, snx, sny, inv_len2)
                        if hit is not None and hit[0] < first_time:
                            first = shape_id
                            first_time, cnx, cny, cdepth = hit
                if first < 0:
                    x = x + dx
                    y = y + dy
                    break
                x = x + dx * first_time
                y = y + dy * first_time
                remaining -= remaining * first_time
                # ---- the contact (section 6.5) ----
                cvx = vx + w * radius * cny
                cvy = vy - w * radius * cnx
                vn = cvx * cnx + cvy * cny
                if vn < 0:
                    e = restitution if vn < -threshold else 0.0
                    jn = -(1 + e) * vn / inv_mass
                    vx += jn * inv_mass * cnx
                    vy += jn * inv_mass * cny
                    vt = -cvx * cny + cvy * cnx
                    jt = -vt / kt
                    max_friction = friction * jn
                    jt = max_friction if jt > max_friction else (-max_friction if jt < -max_friction else jt)
                    vx -= jt * inv_mass * cny
                    vy += jt * inv_mass * cnx
                    w -= jt * radius * inv_inertia
                correction = cdepth - slop
                if correction > 0:
                    x += cnx * correction * fraction
                    y += cny * correction * fraction
        tick += 1
        if on_tick is not None:
            on_tick(tick, (x, y, vx, vy, angle, w))
        # ---- landing (section 8) ----
        if y > line_y or tick >= max_ticks:
            bucket = board.bucket_at(x)
            return {
                'bucket': bucket,
                'multiplier': board.multipliers[bucket],
                'ticks': tick,
                'stateHash': body_state_hash(x, y, vx, vy, angle, w),
            }


def _sweep_point(px, py, dx, dy, cx, cy, reach):
    """First contact of a point moving by (dx, dy) with the disc of `reach` at (cx, cy): (t, nx, ny, depth) or None."""
    mx = px - cx
    my = py - cy
    b = mx * dx + my * dy
    if b >= 0:
        return None
    c = mx * mx + my * my - reach * reach
    if c <= 0:
        return _touching_now(mx, my, c + reach * reach, reach)
    a = dx * dx + dy * dy
    discriminant = b * b - a * c
    if discriminant < 0:
        return None
    t = c / (-b + math.sqrt(discriminant))
    if t > 1:
        return None
    return (t, (mx + dx * t) / reach, (my + dy * t) / reach, 0.0)


def _touching_now(qx, qy, dist2, reach):
    if dist2 > 0:
        dist = math.sqrt(dist2)
        return (0.0, qx / dist, qy / dist, reach - dist)
    return (0.0, 0.0, -1.0, reach)


def _sweep_segment(x, y, reach, dx, dy, ax, ay, bx, by, nx, ny, inv_len2):
    """First contact of the ball with the wall from A to B: (t, nx, ny, depth) or None (section 6.4)."""
    ex = bx - ax
    ey = by - ay
    u = ((x - ax) * ex + (y - ay) * ey) * inv_len2
    u = 0.0 if u < 0 else (1.0 if u > 1 else u)
    qx = x - (ax + ex * u)
    qy = y - (ay + ey * u)
    dist2 = qx * qx + qy * qy
    if dist2 <= reach * reach:
        if qx * dx + qy * dy >= 0:
            return None
        return _touching_now(qx, qy, dist2, reach)
    side = (x - ax) * nx + (y - ay) * ny
    if side < 0:
        nx = -nx
        ny = -ny
        side = -side
    approach = dx * nx + dy * ny
    if approach < 0 and side >= reach:
        t = (side - reach) / -approach
        if t > 1:
            return None
        cx = x + dx * t
        cy = y + dy * t
        v = ((cx - ax) * ex + (cy - ay) * ey) * inv_len2
        if v >= 0 and v <= 1:
            return (t, nx, ny, 0.0)
    hit_a = _sweep_point(x, y, dx, dy, ax, ay, reach)
    hit_b = _sweep_point(x, y, dx, dy, bx, by, reach)
    if hit_a is not None and (hit_b is None or hit_a[0] <= hit_b[0]):
        return hit_a
    return hit_b
