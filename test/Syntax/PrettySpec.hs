-- | The printer: normalised layout, minimal parentheses, literals, and the
-- round trip parse (pretty m) == m (up to positions) on generated trees.
module Syntax.PrettySpec (spec) where

import Data.Ratio ((%))
import Data.Text (Text)
import qualified Data.Text as T
import Stref.Generate.Syntax
import Stref.Policy
import Stref.Syntax
import Stref.Syntax.Parser
import Stref.Syntax.Pretty
import Stref.Verification
import Test.Hspec
import Test.QuickCheck

pe :: Text -> Either String Text
pe t = either (Left . show) (Right . prettyExpr) (parseExpression mastertoolXE t)

roundTripExpr :: Expr () -> Property
roundTripExpr e =
  let printed = prettyExpr e
   in counterexample (T.unpack printed) $
        fmap (() <$) (parseExpression mastertoolXE printed) === Right e

roundTripModule :: Module () -> Property
roundTripModule m =
  let printed = prettyModule m
   in counterexample (T.unpack printed) $
        fmap (() <$) (parseModule mastertoolXE "generated.st" printed) === Right m

spec :: Spec
spec = do
  describe "parentheses" $ do
    it "keeps only those the precedence needs" $ do
      pe "((a + b)) * c" `shouldBe` Right "(a + b) * c"
      pe "a + (b * c)" `shouldBe` Right "a + b * c"
      pe "(NOT a) AND b" `shouldBe` Right "NOT a AND b"
      pe "NOT (a AND b)" `shouldBe` Right "NOT (a AND b)"
      pe "a OR (b AND c)" `shouldBe` Right "a OR b AND c"
      pe "(a OR b) AND c" `shouldBe` Right "(a OR b) AND c"
    it "keeps the right operand of a left-associative operator in parentheses" $ do
      pe "(10 - 4) - 3" `shouldBe` Right "10 - 4 - 3"
      pe "10 - (4 - 3)" `shouldBe` Right "10 - (4 - 3)"
      pe "100 / (10 / 5)" `shouldBe` Right "100 / (10 / 5)"
    it "writes & as AND and unary minus next to its operand" $ do
      pe "a & b" `shouldBe` Right "a AND b"
      pe "-(a * b)" `shouldBe` Right "-(a * b)"
      pe "- -a" `shouldBe` Right "- -a"
      pe "a * -b" `shouldBe` Right "a * -b"

  describe "literals" $ do
    it "writes integers in their base, hex digits in upper case" $ do
      prettyLiteral (LInt 170 16) `shouldBe` "16#AA"
      prettyLiteral (LInt 9 2) `shouldBe` "2#1001"
      prettyLiteral (LInt 303 8) `shouldBe` "8#457"
      prettyLiteral (LInt 1165405007 16) `shouldBe` "16#4576AB4F"
      prettyLiteral (LInt 12547 10) `shouldBe` "12547"
    it "writes reals as exact decimals" $ do
      prettyLiteral (LReal (134 % 10000)) `shouldBe` "0.0134"
      prettyLiteral (LReal 1000000) `shouldBe` "1000000.0"
      prettyLiteral (LReal (12544879 % 10000)) `shouldBe` "1254.4879"
      prettyLiteral (LReal (1 % 8)) `shouldBe` "0.125"
    it "writes booleans as TRUE and FALSE" $
      map prettyLiteral [LBool True, LBool False] `shouldBe` ["TRUE", "FALSE"]

  describe "layout" $
    it "prints a module with upper-case keywords, two-space indentation and ELSIF" $ do
      let src = "program p var x : int; end_var if x = 1 then x := 2; elseif x = 2 then x := 3; else ; end_if; end_program"
      fmap prettyModule (parseModule mastertoolXE "t.st" src)
        `shouldBe` Right
          ( T.unlines
              [ "PROGRAM p"
              , "VAR"
              , "  x : INT;"
              , "END_VAR"
              , "  IF x = 1 THEN"
              , "    x := 2;"
              , "  ELSIF x = 2 THEN"
              , "    x := 3;"
              , "  ELSE"
              , "    ;"
              , "  END_IF;"
              , "END_PROGRAM"
              ]
          )

  describe "errors on damaged programs" $
    it "have a documented kind and a position inside the text" $
      withMaxSuccess 200 $
        forAll genModule $ \m ->
          let printed = prettyModule m
           in forAll (choose (0, T.length printed)) $ \at ->
                forAll (elements ["", "$", ";", "(*", "END_IF", ")", "_", "#", "1.", "%", "X", "2#2"]) $ \insert ->
                  forAll (choose (0, 3)) $ \deleted ->
                    let damaged = T.take at printed <> insert <> T.drop (at + deleted) printed
                     in counterexample (T.unpack damaged) $ case parseModule mastertoolXE "d.st" damaged of
                          Right _ -> property True
                          Left e ->
                            let Pos l c = vePos e
                                ls = T.lines damaged
                             in counterexample (show e) $
                                  veKind e `elem` syntaxKinds
                                    .&&. l >= 1
                                    .&&. l <= length ls + 1
                                    .&&. c >= 1
                                    .&&. c <= 1 + maybe 0 T.length (lookupLine (l - 1) ls)

  describe "round trip" $ do
    it "parse (prettyExpr e) == e for generated expressions" $
      withMaxSuccess 1000 $ forAll (sized (\n -> genExpr (min 12 n))) roundTripExpr
    it "parse (prettyModule m) == m for generated modules" $
      withMaxSuccess 300 $ forAll genModule roundTripModule

syntaxKinds :: [Text]
syntaxKinds =
  [ "invalid-char", "invalid-symbol", "comment-not-closed", "expected-token", "unexpected-after"
  , "unexpected", "unsupported-type", "invalid-operand", "nesting-too-deep"
  ]

lookupLine :: Int -> [a] -> Maybe a
lookupLine i xs = case drop i xs of
  (x : _) | i >= 0 -> Just x
  _ -> Nothing
