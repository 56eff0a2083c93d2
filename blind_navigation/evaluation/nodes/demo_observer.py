#!/usr/bin/env python3
"""The demo_observer node of launch/demo.launch (class: blind_navigation/evaluation/observer.py)."""
from blind_navigation.evaluation.observer import DemoObserver, main as observe


def main():
    observe('demo_observer', DemoObserver)


if __name__ == '__main__':
    main()
