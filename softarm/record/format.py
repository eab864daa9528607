"""The softarm-recording/3 format (docs/recording.md): topics, schemas and metadata names, shared by writer and reader.

/3 adds the disturbances to /2: their list in the model metadata and `/arm/disturbance` on every frame.
"""

from typing import TYPE_CHECKING

import orjson

if TYPE_CHECKING:
    from softarm.sensors import SensorKind

FORMAT = "softarm-recording/3"
FORMAT_NAME, FORMAT_VERSION = FORMAT.split("/")
FORMAT_VERSION_NUMBER = int(FORMAT_VERSION)

META_MODEL = "softarm"
META_RUN = "softarm.run"

IMAGE = "/camera/image"
STRETCH = "/arm/stretch"
NODES = "/arm/nodes"
EXCITATION = "/arm/excitation"
DISTURBANCE = "/arm/disturbance"
ACTIVATION = "/arm/activation"  # only in the recordings of a commanded arm (its model has `muscles`)
TOPICS = (IMAGE, STRETCH, NODES, EXCITATION)  # in every version; /3 adds DISTURBANCE

IMPORTED = "imported"  # the model document's `kind` of a recording imported from a robot's log (no nodes)

POSITION_DECIMALS = 9  # node positions are written to the nanometre


def json_schema(title: str, description: str, properties: dict) -> bytes:
    return orjson.dumps({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": title,
        "description": description,
        "type": "object",
        "properties": {"t": {"type": "number", "description": "time since the start of the run, s"}, **properties},
        "required": ["t", *properties],
    }, option=orjson.OPT_SORT_KEYS)


_NUMBERS = {"type": "array", "items": {"type": "number"}}

JSON_SCHEMAS = {
    STRETCH: ("softarm.Stretch", json_schema(
        "softarm.Stretch", "Stretch sensor readings: change of distance between two nodes",
        {"stretch": {**_NUMBERS, "description": "one reading per sensor, m"}})),
    NODES: ("softarm.Nodes", json_schema(
        "softarm.Nodes", "Positions of every node of the arm",
        {"positions": {"type": "array", "items": {**_NUMBERS, "minItems": 2, "maxItems": 2},
                       "description": "[x, y] per node, m (y up)"}})),
    EXCITATION: ("softarm.Excitation", json_schema(
        "softarm.Excitation", "Displacement of the driven nodes along the drive direction, f(t + t0)",
        {"displacement": {"type": "number", "description": "m, along the excitation direction of the metadata"}})),
    DISTURBANCE: ("softarm.Disturbance", json_schema(
        "softarm.Disturbance", "The disturbances acting at this frame (start <= t < end)",
        {"active": {"type": "array", "items": {"type": "integer", "minimum": 0},
                    "description": "indices into the model metadata's disturbances"}})),
}

# In the recordings whose model lists an obstacle, /arm/disturbance also says which ones the arm touches: the label
# of contact (an obstacle acts on the body only while touched). Recordings without one keep the schema above.
CONTACT_SCHEMA = {DISTURBANCE: ("softarm.Disturbance", json_schema(
    "softarm.Disturbance", "The disturbances acting at this frame (start <= t < end), and the obstacles touched",
    {"active": {"type": "array", "items": {"type": "integer", "minimum": 0},
                "description": "indices into the model metadata's disturbances"},
     "touching": {"type": "array", "items": {"type": "integer", "minimum": 0},
                  "description": "the active obstacles that some free node is inside (|x - centre| < radius)"}}))}



def sensor_schema(kind: "SensorKind") -> dict[str, tuple[str, bytes]]:
    """The channel of a sensor kind other than the stretch (softarm.sensors), in the recordings that place it."""
    return {kind.topic: (kind.title, json_schema(kind.title, kind.description, {
        kind.field: {**_NUMBERS, "description": f"one reading per sensor of the model's `{kind.name}`, {kind.unit}"}}))}


ACTIVATION_SCHEMA = {ACTIVATION: ("softarm.Activation", json_schema(
    "softarm.Activation", "The muscles of a commanded arm (docs/model.md, Muscles), one value per group",
    {"command": {**_NUMBERS, "description": "the command held from this frame to the next, 0..1"},
     "activation": {**_NUMBERS, "description": "the activation at this frame, 0..1"}}))}
