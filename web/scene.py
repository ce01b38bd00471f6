"""The shared 3D scene: SDO at its true attitude in the GCI frame (viser's
world), its estimated attitude as a ghost, the target frame, and what the
telemetry can place: the Sun, the Earth and the orbit track, wheel speeds,
thruster plumes, the guide telescopes' field of view.

Elements whose telemetry fields are absent stay hidden (docs/console.md lists
the names); nothing here invents data. Quaternions are scalar-first q_BN
(body to GCI), which is viser's local-to-parent wxyz.
"""
from __future__ import annotations

import collections

import numpy as np

GOLD, WHITE, PANEL, GREY = (212, 175, 55), (235, 235, 235), (30, 50, 120), (150, 150, 150)
SUN_YELLOW, EARTH_BLUE, PLUME = (255, 210, 40), (40, 110, 220), (255, 140, 30)
EARTH_DIST = 18.0           # scene units from the spacecraft to the Earth's centre (not to scale)
R_EARTH_M = 6_378_137.0


def quat_rotate(q, v):
    """Rotate v by the scalar-first unit quaternion q (body to parent)."""
    w, x, y, z = q
    u = np.array([x, y, z])
    v = np.asarray(v, float)
    return v + 2.0 * np.cross(u, np.cross(u, v) + w * v)


def quat_from_z(d):
    """A wxyz quaternion turning +Z onto the unit vector d (for cylinders)."""
    d = np.asarray(d, float) / np.linalg.norm(d)
    z = np.array([0.0, 0.0, 1.0])
    c = float(np.dot(z, d))
    if c < -0.999999:
        return (0.0, 1.0, 0.0, 0.0)
    axis = np.cross(z, d)
    q = np.array([1.0 + c, *axis])
    return tuple(q / np.linalg.norm(q))


def vec(frame: dict, prefix: str, axes=("x", "y", "z"), unit: str = "") -> np.ndarray | None:
    """A vector field group from a frame, or None when telemetry lacks it."""
    names = [f"{prefix}_{a}{unit}" for a in axes]
    if not all(n in frame for n in names):
        return None
    return np.array([frame[n] for n in names], float)


class SpacecraftScene:
    def __init__(self, server, sc):
        self.server, self.sc = server, sc
        s = server.scene
        s.set_up_direction("+z")
        s.add_frame("/gci", axes_length=1.5, axes_radius=0.02, origin_radius=0.05)
        s.add_label("/gci/label", "GCI", position=(0.0, -1.0, -1.9))
        self.body = s.add_frame("/sdo", axes_length=3.2, axes_radius=0.03)
        self._build_bus("/sdo")
        self.ghost = s.add_frame("/estimate", axes_length=2.6, axes_radius=0.015, origin_radius=0.01)
        # drawn a little larger than the bus so that it shows around it
        s.add_box("/estimate/bus", color=(0, 150, 255), dimensions=(2.6, 2.6, 2.6), wireframe=True)
        self.target = s.add_frame("/target", axes_length=4.5, axes_radius=0.012, origin_radius=0.01)
        s.add_label("/target/label", "target", position=(4.6, 0.0, 0.0))
        self.wheel_labels = self._build_wheels("/sdo")
        self.plumes = self._build_plumes("/sdo")
        self.cgt = self._build_cgt("/sdo")
        self.sun = s.add_arrows("/sun", points=np.array([[[0, 0, 0], [9.0, 0, 0]]], float), colors=SUN_YELLOW,
                                shaft_radius=0.03, head_radius=0.15, head_length=0.4, visible=False)
        self.sun_label = s.add_label("/sun_label", "Sun", position=(9.5, 0, 0), visible=False)
        self.earth = s.add_icosphere("/earth", radius=1.0, color=EARTH_BLUE, visible=False)
        self.track = None
        self._track_pts: collections.deque = collections.deque(maxlen=400)

    # -- construction ----------------------------------------------------------------
    def _build_bus(self, root: str) -> None:
        s = self.server.scene
        s.add_box(f"{root}/bus", color=GOLD, dimensions=(2.2, 2.2, 2.2))
        # the instrument module sits on +X, the boresight that points at the Sun
        s.add_box(f"{root}/instruments", color=WHITE, dimensions=(1.4, 1.9, 1.9), position=(1.8, 0.0, 0.0))
        for side in (1, -1):
            s.add_box(f"{root}/array_{'py' if side > 0 else 'my'}", color=PANEL, dimensions=(0.05, 3.4, 1.9),
                      position=(0.2, side * 3.0, 0.0))
            s.add_box(f"{root}/boom_{'py' if side > 0 else 'my'}", color=GREY, dimensions=(0.08, 0.6, 0.08),
                      position=(0.2, side * 1.35, 0.0))
        # the high-gain antennas on booms at the aft end
        for side in (1, -1):
            tag = "pz" if side > 0 else "mz"
            s.add_box(f"{root}/hga_boom_{tag}", color=GREY, dimensions=(0.08, 0.08, 1.2),
                      position=(-1.2, 0.0, side * 1.6))
            s.add_cylinder(f"{root}/hga_{tag}", radius=0.55, height=0.08, color=WHITE,
                           position=(-1.2, 0.0, side * 2.25), wxyz=quat_from_z((-1.0, 0.0, 0.0)))

    def _build_wheels(self, root: str) -> list:
        s, labels = self.server.scene, []
        for i, axis in enumerate(self.sc.wheels.axes_B):
            pos = 0.75 * np.asarray(axis) + np.array([-0.4, 0.0, 0.0])
            s.add_cylinder(f"{root}/wheel_{i + 1}", radius=0.25, height=0.1, color=(90, 90, 90),
                           position=tuple(pos), wxyz=quat_from_z(axis))
            labels.append(s.add_label(f"{root}/wheel_{i + 1}/label", f"W{i + 1}", position=(0.0, 0.0, 0.3),
                                      font_screen_scale=0.8))
        return labels

    def _build_plumes(self, root: str) -> list:
        thrusters = getattr(getattr(self.sc, "thrusters", None), "units", None) or []
        plumes = [self._plume(f"{root}/plume_{i + 1}", t, 0.12, 0.8) for i, t in enumerate(thrusters)]
        engine = getattr(self.sc, "main_engine", None)
        self.engine_plume = None if engine is None else self._plume(f"{root}/engine_plume", engine, 0.3, 2.5)
        return plumes

    def _plume(self, name: str, unit, radius: float, length: float):
        exhaust = -np.asarray(unit.direction_B, float)   # the plume leaves opposite to the force
        pos = np.asarray(unit.position_B_m, float) + 0.5 * length * exhaust
        return self.server.scene.add_cylinder(name, radius=radius, height=length, color=PLUME, opacity=0.7,
                                              position=tuple(pos), wxyz=quat_from_z(exhaust), visible=False)

    def _build_cgt(self, root: str):
        """The guide telescopes' field of view (as a cone around the first
        unit's boresight), when the spacecraft file describes them."""
        sensors = getattr(self.sc, "sensors", None)
        gts = getattr(sensors, "guide_telescopes", None) or getattr(self.sc, "guide_telescopes", None)
        half = getattr(gts, "fov_half_angle_deg", None)
        units = getattr(gts, "units", None)
        if half is None or not units:
            return None
        q_BG = getattr(units[0], "q_BG", (1.0, 0.0, 0.0, 0.0))
        axis = quat_rotate(q_BG, (1.0, 0.0, 0.0))          # a telescope's boresight is its +X
        length = 6.0
        pos = 2.5 * axis + 0.5 * length * axis               # from the front of the instrument module
        return self.server.scene.add_cylinder(f"{root}/cgt_fov", radius=length * np.tan(np.radians(half)),
                                              height=length, color=(255, 255, 150), opacity=0.2,
                                              position=tuple(pos), wxyz=quat_from_z(axis), visible=False)

    # -- updates ------------------------------------------------------------------------
    def update(self, frame: dict) -> None:
        q = vec(frame, "q_BN", ("w", "x", "y", "z"))
        if q is None:
            return
        self.body.wxyz = q
        q_est = vec(frame, "q_est_BN", ("w", "x", "y", "z"))
        self.ghost.visible = q_est is not None
        if q_est is not None:
            self.ghost.wxyz = q_est
        q_RN = vec(frame, "q_RN", ("w", "x", "y", "z"))
        self.target.visible = q_RN is not None
        if q_RN is not None:
            self.target.wxyz = q_RN
        self._update_sun(frame, q)
        self._update_earth(frame)
        for i, label in enumerate(self.wheel_labels):
            rpm = frame.get(f"wheel_speed_{i + 1}_rpm")
            if rpm is not None:
                label.text = f"W{i + 1} {rpm:+.0f} rpm"
        for i, plume in enumerate(self.plumes):
            plume.visible = bool(frame.get(f"thr_pulses_{i + 1}", 0) > 0)
        if self.engine_plume is not None:
            self.engine_plume.visible = bool(frame.get("engine_on", 0) > 0)
        if self.cgt is not None:   # shown while a guide telescope sees the Sun
            self.cgt.visible = any(frame.get(f"gt_valid_{i}", 0) > 0 for i in range(1, 5))

    def _update_sun(self, frame: dict, q_BN) -> None:
        sun = vec(frame, "sun_N")
        if sun is None:
            sun_B = vec(frame, "sun_B")
            sun = None if sun_B is None else quat_rotate(q_BN, sun_B)
        visible = sun is not None and np.linalg.norm(sun) > 0
        self.sun.visible = self.sun_label.visible = visible
        if visible:
            tip = 9.0 * sun / np.linalg.norm(sun)
            self.sun.points = np.array([[[0.0, 0.0, 0.0], tip]])
            self.sun_label.position = tuple(tip * 1.06)

    def _update_earth(self, frame: dict) -> None:
        r = vec(frame, "r_N", unit="_m")
        self.earth.visible = r is not None
        if r is None or np.linalg.norm(r) == 0:
            return
        scale = EARTH_DIST / np.linalg.norm(r)       # the Earth is drawn EARTH_DIST away, in the true direction
        centre = -r * scale
        self.earth.position = tuple(centre)
        self.earth.scale = R_EARTH_M * scale
        self._track_pts.append(r.copy())
        if len(self._track_pts) >= 2:
            pts = (np.array(self._track_pts) - r) * scale
            segments = np.stack([pts[:-1], pts[1:]], axis=1)
            if self.track is None:
                self.track = self.server.scene.add_line_segments("/orbit_track", points=segments,
                                                                 colors=(200, 200, 255), thickness=0.04)
            else:
                self.track.points = segments

    def reset(self) -> None:
        """A new run: forget the orbit track."""
        self._track_pts.clear()
