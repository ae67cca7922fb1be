"""laserpeople.tracking.mht"""
