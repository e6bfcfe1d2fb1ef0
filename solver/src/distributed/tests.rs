use super::*;

#[test]
fn element_ranges_cover_the_elements_in_order_and_nearly_equal() {
    for (elements, size) in [(10, 3), (3, 4), (21600, 2), (0, 2), (7, 1)] {
        let ranges = element_ranges(elements, size);
        assert_eq!(ranges.len(), size);
        assert_eq!(ranges[0].start, 0);
        assert_eq!(ranges[size - 1].end, elements);
        for pair in ranges.windows(2) {
            assert_eq!(
                pair[0].end, pair[1].start,
                "{elements} on {size}: consecutive"
            );
        }
        let (min, max) = (
            ranges.iter().map(|r| r.len()).min().unwrap(),
            ranges.iter().map(|r| r.len()).max().unwrap(),
        );
        assert!(max - min <= 1, "{elements} on {size}: {min}..{max}");
    }
}
