"""What the session studies share: robots generated at random within the documented ranges, and
a store that puts a robot file's true geometry in force (the oracle)."""
import math
import subprocess


def generate_robot(rng, draw_slip):
    """Wheels 30-160 mm, wheelbase 1.8-5 diameters, each true wheel within 0.5 % of the nominal,
    the true wheelbase within 3 %, sometimes (30 %) an arc wheelbase up to 1.5 % above it, a few
    encoder resolutions; `draw_slip(rng)` the slip_sigma."""
    d = round(math.exp(rng.uniform(math.log(30.0), math.log(160.0))), 1)
    b = round(d * rng.uniform(1.8, 5.0), 1)
    doc = {
        "wheel_diameter_mm": d,
        "wheelbase_mm": b,
        "counts_per_rev": rng.choice([360, 1024, 1440, 2048, 4096]),
        "true_left_diameter_mm": round(d * (1.0 + rng.uniform(-0.005, 0.005)), 3),
        "true_right_diameter_mm": round(d * (1.0 + rng.uniform(-0.005, 0.005)), 3),
        "true_wheelbase_mm": round(b * (1.0 + rng.uniform(-0.03, 0.03)), 2),
        "slip_sigma": draw_slip(rng),
    }
    if rng.random() < 0.3:
        doc["true_wheelbase_arc_mm"] = round(
            doc["true_wheelbase_mm"] * (1.0 + rng.uniform(0.002, 0.015)), 2)
    return doc


def oracle_store(bindir, doc, robot, store):
    """Writes `store`: odocal-sim's parameters with the robot file's true geometry in force."""
    d = doc["wheel_diameter_mm"]
    script = "set c_l %.6f\nset c_r %.6f\nset wheelbase_mm %.4f\n" % (
        doc["true_left_diameter_mm"] / d, doc["true_right_diameter_mm"] / d,
        doc["true_wheelbase_mm"])
    if "true_wheelbase_arc_mm" in doc:
        script += "set wheelbase_arc_mm %.4f\n" % doc["true_wheelbase_arc_mm"]
    script += "save\n"
    subprocess.run([bindir + "/odocal-sim", "--robot", robot, "--store", store],
                   input=script, capture_output=True, text=True, check=True)
    return store
