#!/usr/bin/env python3
"""The demo_observer node of make demo and launch/demo.launch (class:
blind_navigation/evaluation/observer.py). Exit status 0 when the robot came home,
1 when the return aborted or the demo timed out."""
import sys

from blind_navigation.evaluation.observer import DemoObserver, main as observe


def main():
    node = observe('demo_observer', DemoObserver)
    sys.exit(0 if node.state == 'home' else 1)


if __name__ == '__main__':
    main()
