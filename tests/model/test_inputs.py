"""What a training reads when `train.inputs` names nothing: the paper's stretch for a few recordings, and for a
corpus all the arm feels (the stretch, every other kind each recording carries or [sensing] places) and its
command."""

from softarm.config import load_config, override
from softarm.corpus.manifest import MIN_CORPUS
from softarm.model.inputs import chosen_inputs

BEND = [[4, 10, 16], [16, 22, 28], [28, 34, 40], [40, 46, 55]]
CARRIES = {"sensors": [[3, 27]], "bend": BEND}
LACKS = {"sensors": [[3, 27]]}


def test_a_few_recordings_read_the_stretch_alone_even_with_bend_sensors():
    assert chosen_inputs([], [CARRIES] * MIN_CORPUS, load_config(), MIN_CORPUS) == ("stretch",)


def test_a_corpus_reads_every_sensor_kind_all_its_recordings_carry_then_the_drive():
    corpus = [CARRIES] * (MIN_CORPUS + 1)
    assert chosen_inputs([], corpus, load_config(), MIN_CORPUS) == ("stretch", "bend", "drive")
    assert chosen_inputs([], corpus[:-1] + [LACKS], load_config(), MIN_CORPUS) == ("stretch", "drive")


def test_bend_sensors_placed_for_reading_count_as_carried():
    placed = override(load_config(), {"sensing.bend": BEND})
    assert chosen_inputs([], [LACKS] * (MIN_CORPUS + 1), placed, MIN_CORPUS) == ("stretch", "bend", "drive")


def test_the_inputs_asked_for_win():
    assert chosen_inputs(["stretch", "drive"], [CARRIES] * 9, load_config(), MIN_CORPUS) == ("stretch", "drive")
