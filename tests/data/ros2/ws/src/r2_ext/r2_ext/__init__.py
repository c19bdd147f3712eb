"""A launch front-end extension: the tag <mark label="..."/> (logs nothing, starts nothing)."""

from launch.action import Action
from launch.frontend import expose_action


@expose_action("mark")
class Mark(Action):
    def __init__(self, label: str, **kwargs) -> None:
        super().__init__(**kwargs)
        self.label = label

    @classmethod
    def parse(cls, entity, parser):
        _, kwargs = super().parse(entity, parser)
        kwargs["label"] = entity.get_attr("label")
        return cls, kwargs

    def execute(self, context):
        return None
